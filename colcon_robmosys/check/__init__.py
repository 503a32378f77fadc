# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The check stage: every rule over every model file of a workspace, at once."""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from colcon_robmosys.check.cache import file_key, ModelCache
from colcon_robmosys.check.file import broken_external_components, check_file
from colcon_robmosys.check.forked import fork_map, MIN_FILES_PER_WORKER
from colcon_robmosys.check.index import InterfaceIndex
from colcon_robmosys.check.results import CheckedFile, LoadResult
from colcon_robmosys.check.rules import check_workspace, RULES
from colcon_robmosys.check.subsystems import expand_subsystems
from colcon_robmosys.check.underlays import installed_models, shadow_message
from colcon_robmosys.errors import Diagnostic, RobmosysError
from colcon_robmosys.model import rosidl
from colcon_robmosys.model.files import find_model_files, model_dependencies
from colcon_robmosys.model.loader import read_model_bytes
from colcon_robmosys.model.schema import warm_fast_check
from colcon_robmosys.model.types import model_key, ModelFile, Workspace

__all__ = ['CheckedFile', 'find_model_files', 'load_model_file', 'load_workspace',
           'LoadResult', 'ModelCache', 'RULES']


def load_model_file(path: Path) -> ModelFile:
    """Load and check a single file on its own.

    :raises RobmosysError: with every problem of the file
    """
    checked = check_file(path, read_model_bytes(path))
    if checked.diagnostics:
        raise RobmosysError(checked.diagnostics)
    assert checked.model_file is not None
    return checked.model_file


def _check_forked(read: dict[Path, tuple[bytes, str]], cache: ModelCache | None,
                  workers: int) -> dict[Path, CheckedFile]:
    """Check the files the cache lacks in forked workers, if they are enough for two.

    A worker stores what it checked in the cache, as this process would.

    :param read: the files read -> their content and key
    :returns: what the workers checked
    """
    fresh = [(path, raw, key) for path, (raw, key) in read.items()
             if cache is None or not cache.has(key)]
    workers = min(workers, len(fresh) // MIN_FILES_PER_WORKER)
    if workers < 2:
        return {}
    # compiled once, here: the workers inherit it
    if cache is not None:
        cache.use_compiled_schema()
    else:
        warm_fast_check()

    def check_share(share: list[tuple[Path, bytes, str]]) -> list[CheckedFile]:
        checked = []
        for path, raw, key in share:
            checked.append(check_file(path, raw))
            if cache is not None:
                cache.put(key, checked[-1])
        return checked

    shares = [fresh[worker::workers] for worker in range(workers)]
    return {path: checked for share, results in zip(shares, fork_map(check_share, shares))
            for (path, _, _), checked in zip(share, results)}


def load_workspace(paths: Iterable[Path],
                   index: InterfaceIndex | None = None,
                   cache: ModelCache | None = None, workers: int = 1) -> LoadResult:
    """Load the model files and check them together.

    Every file is loaded even when others are broken, so that one run
    reports every problem of the workspace.

    :param cache: where files checked by an earlier run are kept, by content
    :param workers: the most processes to check files in at once (see
      :mod:`colcon_robmosys.check.forked`): one is forked for every
      :data:`MIN_FILES_PER_WORKER` files the cache does not have
    """
    if rosidl.MISSING is not None:
        # nothing can be checked without it: one error, and every file broken,
        # so that the build of its packages fails
        return LoadResult(Workspace(()), [Diagnostic(rosidl.MISSING_LOCATION, rosidl.MISSING)],
                          {str(path): [] for path in sorted(set(paths))})
    files: list[ModelFile] = []
    diagnostics: list[Diagnostic] = []
    broken: dict[str, list[tuple[str, str]]] = {}
    keys: dict[str, str] = {}
    # external components of broken files: no "unknown component" for their instances
    broken_external: set[str] = set()

    def checked_file(path: Path, raw: bytes, key: str | None = None) -> CheckedFile:
        key = keys[str(path)] = key or file_key(path, raw)
        checked = cache.get(key) if cache is not None else None
        if checked is None:
            if cache is not None:
                cache.use_compiled_schema()
            checked = check_file(path, raw)
            if cache is not None:
                cache.put(key, checked)
        return checked

    #: each file -> its content and key, None where it cannot be read
    read: dict[Path, tuple[bytes, str] | None] = {}
    for path in sorted(set(paths)):
        try:
            raw = read_model_bytes(path)
            read[path] = (raw, file_key(path, raw))
        except RobmosysError as exc:
            diagnostics.extend(exc.diagnostics)
            read[path] = None
    forked = _check_forked({p: r for p, r in read.items() if r is not None}, cache, workers)
    for path, content in read.items():
        if content is None:
            broken[str(path)] = []
            continue
        checked = forked.get(path)
        if checked is None:
            checked = checked_file(path, *content)
        else:
            keys[str(path)] = content[1]
        if checked.model_file is not None:
            # the models that passed: the rules of the workspace check them
            files.append(checked.model_file)
        if checked.diagnostics:
            diagnostics.extend(checked.diagnostics)
            broken[str(path)] = list(checked.broken)
            broken_external.update(broken_external_components(path, checked.model_file))
    index = index or InterfaceIndex.from_environment()
    # then what the underlays installed, for the packages the workspace lacks
    present = {model_key(m) for f in files for m in f.models} | {
        name for declared in broken.values() for name, _ in declared}
    underlays = installed_models(
        index, present, lambda path: checked_file(path, path.read_bytes()))
    files += underlays.files
    diagnostics += underlays.diagnostics
    # the rules below see every system with the instances of its subsystems
    files, problems = expand_subsystems(
        files, {name for declared in broken.values() for name, _ in declared})
    diagnostics += problems
    if cache is not None:
        cache.prune(set(keys.values()))
    ctx = check_workspace(
        files, index,
        [name for declared in broken.values() for name, _ in declared] +
        sorted(broken_external))
    for model_file in files:
        for model in () if model_file.installed else model_file.models:
            for package in model_dependencies(model):
                if package in underlays.shadowed:
                    ctx.warning(model.package, model.info.location, shadow_message(
                        package, underlays.shadowed[package]))
    diagnostics.extend(ctx.diagnostics)
    return LoadResult(Workspace(tuple(files)), sorted(set(diagnostics)),
                      broken, {package: sorted(set(warnings)) for package,
                               warnings in ctx.package_warnings.items()},
                      keys)
