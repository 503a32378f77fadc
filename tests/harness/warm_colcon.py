# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""
colcon, forked from a process that has loaded it once: for tests that run it hundreds of times.

Running ``colcon`` costs about 1.5 s before it looks at a workspace: the interpreter
starts, colcon loads some 150 extensions, colcon-robmosys compiles its schema. A test
that runs colcon on each of 144 broken models paid that 288 times. :class:`WarmColcon`
starts one server process that imports colcon and every extension once, then forks it
for each run: the child calls ``colcon_core.command.main`` (what the ``colcon`` script
calls) in the run's working folder and environment, with its output in files, and exits
with its return code. What a run sees of colcon is what the command sees; only the
start of the interpreter is shared. Every run has a timeout, and the child is killed
with its process group when it passes it; the server ends when the test side closes it.

Run as a script, this module is that server (one JSON request per line on its
standard input, one JSON answer per line on its standard output).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import tempfile
import time
from typing import Any, Mapping, Sequence


class WarmColcon:
    """The test side: start the server, run colcon in it, close it."""

    def __init__(self, timeout: float = 60.0) -> None:
        self._proc = subprocess.Popen(
            [sys.executable, __file__], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            text=True, start_new_session=True)
        self._outputs = tempfile.TemporaryDirectory(prefix='warm-colcon-')
        answer = self._answer(timeout)
        if answer.get('ready') is not True:
            self.close()
            raise RuntimeError(f'the colcon server did not start: {answer}')

    def _answer(self, timeout: float) -> dict[str, Any]:
        assert self._proc.stdout is not None
        # the server answers every request within its timeout (it kills the
        # run that passes it): a server that does not is killed here
        line = _readline(self._proc, timeout + 30.0)
        if not line:
            self.close()
            raise RuntimeError('the colcon server ended or did not answer')
        answer: dict[str, Any] = json.loads(line)
        return answer

    def run(self, args: Sequence[str], *, cwd: Path, env: Mapping[str, str],
            timeout: float = 300.0) -> subprocess.CompletedProcess[str]:
        """Run ``colcon args`` in cwd with env; raise TimeoutExpired past timeout."""
        assert self._proc.stdin is not None
        stdout = Path(self._outputs.name) / 'stdout'
        stderr = Path(self._outputs.name) / 'stderr'
        request = {'argv': list(args), 'cwd': str(cwd), 'env': dict(env),
                   'stdout': str(stdout), 'stderr': str(stderr), 'timeout': timeout}
        self._proc.stdin.write(json.dumps(request) + '\n')
        self._proc.stdin.flush()
        answer = self._answer(timeout)
        out = stdout.read_text(errors='replace')
        err = stderr.read_text(errors='replace')
        command = ['colcon', *args]
        if answer['timed_out']:
            raise subprocess.TimeoutExpired(command, timeout, out, err)
        return subprocess.CompletedProcess(command, answer['returncode'], out, err)

    def close(self) -> None:
        """End the server (and any run it has, with its process group)."""
        if self._proc.poll() is None:
            assert self._proc.stdin is not None
            self._proc.stdin.close()
            try:
                self._proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(self._proc.pid, signal.SIGKILL)
                self._proc.wait()
        if self._proc.stdout is not None:
            self._proc.stdout.close()
        self._outputs.cleanup()


def _readline(proc: subprocess.Popen[str], timeout: float) -> str:
    """Return a line the process prints within timeout, '' if none (then kill it)."""
    import selectors
    assert proc.stdout is not None
    with selectors.DefaultSelector() as selector:
        selector.register(proc.stdout, selectors.EVENT_READ)
        if not selector.select(timeout):
            os.killpg(proc.pid, signal.SIGKILL)
            return ''
    return proc.stdout.readline()


# The server.

def _warm_up() -> None:
    """Import colcon and every extension, and compile what colcon-robmosys compiles once."""
    import colcon_core.command  # noqa: F401 - what the runs call
    from colcon_core.extension_point import get_all_extension_points, load_extension_points
    from colcon_core.location import set_default_config_path
    from colcon_core.logging import colcon_logger
    # what colcon's main does first: some extensions read the path on import
    set_default_config_path(path=Path('~/.colcon').expanduser(), env_var='COLCON_HOME')
    level = colcon_logger.level
    colcon_logger.setLevel(100)  # one that fails to load here is loaded by the run
    for group in get_all_extension_points():
        load_extension_points(group)
    colcon_logger.setLevel(level)
    from colcon_robmosys.model import schema
    schema.is_valid({})


def _child(request: Mapping[str, Any]) -> int:
    """Run colcon as the command would, in the forked child; return its code."""
    from colcon_core.command import main
    os.setpgid(0, 0)
    os.chdir(request['cwd'])
    os.environ.clear()
    os.environ.update(request['env'])
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    for fd, path in ((1, request['stdout']), (2, request['stderr'])):
        handle = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(handle, fd)
        os.close(handle)
    sys.argv = ['colcon', *request['argv']]
    try:
        # the colcon script: sys.exit(main())
        code = main(argv=request['argv'])
    except SystemExit as exit_:
        code = exit_.code
    if code is None or isinstance(code, int):
        return int(code or 0)
    print(code, file=sys.stderr)  # what sys.exit does with any other value
    return 1


def _serve() -> None:
    _warm_up()
    answers = sys.stdout
    print(json.dumps({'ready': True}), file=answers, flush=True)
    for line in sys.stdin:
        request = json.loads(line)
        pid = os.fork()
        if pid == 0:  # the run
            code = 1
            try:
                code = _child(request)
            except BaseException:  # noqa: B902 - told as the run's output
                import traceback
                traceback.print_exc()
            finally:
                sys.stdout.flush()
                sys.stderr.flush()
                os._exit(code)
        try:
            # a process group of its own before a timeout may kill it (the
            # child says so too: whichever comes first)
            os.setpgid(pid, pid)
        except OSError:
            pass
        deadline = time.monotonic() + request['timeout']
        timed_out = False
        while True:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                break
            if time.monotonic() > deadline:
                timed_out = True
                os.killpg(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                break
            time.sleep(0.005)
        returncode = None if timed_out else os.waitstatus_to_exitcode(status)
        print(json.dumps({'returncode': returncode, 'timed_out': timed_out}),
              file=answers, flush=True)


if __name__ == '__main__':
    # run as a script, this folder comes first on sys.path: its modules are
    # not what colcon and its extensions import
    sys.path.remove(str(Path(__file__).resolve().parent))
    _serve()
