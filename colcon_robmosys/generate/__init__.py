# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Generate the files of a package plan, and keep the user's files safe."""

from __future__ import annotations

import ast
from dataclasses import dataclass, field
import hashlib
from pathlib import Path
import re

from colcon_robmosys.errors import Diagnostic, Location, RobmosysError
from colcon_robmosys.generate.render import render
from colcon_robmosys.generate.writer import (
    create_user_file, is_generated, remove_generated, remove_leftovers,
    write_generated)
from colcon_robmosys.ros2.plan import PackagePlan, UserFile

#: Lists, inside a generated package, the files the generation wrote.
MANIFEST = '.robmosys-generated'


@dataclass
class GenerationReport:
    """What a generation did."""

    written: list[Path] = field(default_factory=list)
    unchanged: list[Path] = field(default_factory=list)
    removed: list[Path] = field(default_factory=list)
    created_user_files: list[Path] = field(default_factory=list)


def user_file_problems(user_file: UserFile, path: Path) -> list[Diagnostic]:
    """Check that the user's code defines what the model asks of it."""
    try:
        text = path.read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError) as exc:
        return [Diagnostic(Location(str(path)),
                           f'cannot read the implementation file: {exc}')]
    if path.suffix in ('.hpp', '.h'):
        return _cpp_header_problems(user_file, path, text)
    if not path.suffix == '.py':
        return []
    try:
        tree = ast.parse(text, filename=str(path))
    except SyntaxError as exc:
        return [Diagnostic(Location(str(path), exc.lineno or 0,
                                    exc.offset or 0),
                           f'Python syntax error: {exc.msg}')]
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef) and
               n.name == user_file.required_class]
    skeleton = f'the skeleton {user_file.skeleton_path} of the package shows ' \
        'what the model asks for'
    if not classes:
        return [Diagnostic(Location(str(path), 1, 1),
                           f"no class '{user_file.required_class}' in the "
                           f'implementation file; {skeleton}')]
    cls = classes[0]
    defined = {n.name for n in cls.body
               if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
    return [Diagnostic(Location(str(path), cls.lineno, cls.col_offset + 1),
                       f"class '{cls.name}' lacks the function '{name}' of "
                       f'the model; {skeleton}')
            for name in user_file.required_functions if name not in defined]


def _with_skeleton_path(diagnostic: Diagnostic, plan: PackagePlan,
                        out_dir: Path) -> Diagnostic:
    """Add where the skeleton a message names was written."""
    for user_file in plan.user_files:
        if user_file.skeleton_path and \
                f'skeleton {user_file.skeleton_path} ' in diagnostic.message:
            return Diagnostic(
                diagnostic.location, f'{diagnostic.message}: '
                f'{out_dir / user_file.skeleton_path}', diagnostic.severity)
    return diagnostic


def _cpp_header_problems(user_file: UserFile, path: Path,
                         text: str) -> list[Diagnostic]:
    """Check that a C++ header declares the class and functions of the model.

    A compiler would say so too, but only in the middle of the build and in
    terms of pure virtual functions; this names the function of the model.
    Comments, strings and preprocessor lines are blanked out (keeping line
    and column) so that only declarations count.
    """
    code = _CPP_NOISE.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    skeleton = f'the skeleton {user_file.skeleton_path} of the package shows ' \
        'what the model asks for'
    cls = re.search(rf'\b(?:class|struct)\s+{re.escape(user_file.required_class)}\b'
                    r'[^;{]*\{', code)
    if cls is None:
        return [Diagnostic(Location(str(path), 1, 1),
                           f"no class '{user_file.required_class}' in the "
                           f'implementation file; {skeleton}')]
    line = code.count('\n', 0, cls.start()) + 1
    column = cls.start() - code.rfind('\n', 0, cls.start())
    body = code[cls.end():]
    return [Diagnostic(Location(str(path), line, column),
                       f"class '{user_file.required_class}' lacks the function "
                       f"'{name}' of the model; {skeleton}")
            for name in user_file.required_functions
            if not re.search(rf'\b{re.escape(name)}\s*\(', body)]


#: C++ comments, string and character literals, and preprocessor lines.
_CPP_NOISE = re.compile(
    r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|^[ \t]*#[^\n]*',
    re.DOTALL | re.MULTILINE)


def create_missing_user_files(plan: PackagePlan) -> list[Path]:
    """Create the implementation files the user lacks, from the model.

    Existing files are never touched.
    """
    created = []
    for user_file in plan.user_files:
        path = plan.model_dir / user_file.source_path
        text = render(user_file.template, user_file.context)
        if create_user_file(path, text.encode('utf-8')):
            created.append(path)
    return created


def generate_package(plan: PackagePlan, out_dir: Path) -> GenerationReport:
    """Write the package of a plan into out_dir.

    Everything is rendered and checked before the first file is written, so
    that a problem leaves the previous output as it was.

    :raises RobmosysError: if the user's code is missing or incomplete
    """
    problems: list[Diagnostic] = []
    outputs: dict[str, tuple[bytes, bool]] = {}
    for spec in plan.files:
        outputs[spec.path] = (render(spec.template, spec.context)
                              .encode('utf-8'), spec.executable)
    for user_file in plan.user_files:
        source = plan.model_dir / user_file.source_path
        if not source.is_file():
            problems.append(Diagnostic(
                Location(str(source)),
                'the implementation file is missing: run '
                f"'colcon robmosys-generate --packages-select {plan.name}' "
                'to create it from the model, then fill it in'))
            continue
        problems += user_file_problems(user_file, source)
        outputs[user_file.package_path] = (source.read_bytes(), False)
    if problems:
        problems = [_with_skeleton_path(d, plan, out_dir) for d in problems]
        for user_file in plan.user_files:
            # an error that points at a skeleton finds it up to date
            path = out_dir / user_file.skeleton_path
            if user_file.skeleton_path in outputs and \
                    any(str(path) in d.message for d in problems):
                data, executable = outputs[user_file.skeleton_path]
                write_generated(path, data, executable=executable)
        raise RobmosysError(problems)

    report = GenerationReport()
    if out_dir.is_dir():
        report.removed += remove_leftovers(out_dir)
    manifest_path = out_dir / MANIFEST
    previous = read_manifest(manifest_path)
    final: Manifest = {relative: {_digest(data)}
                       for relative, (data, _) in outputs.items()}
    # a run killed half-way must leave every file it wrote known as ours:
    # first record the old and the new content of each file, then write
    pending: Manifest = dict(previous)
    for relative, digests in final.items():
        pending[relative] = (previous.get(relative) or set()) | (digests or set())
    if pending != previous:
        _write_manifest(manifest_path, pending)
    for relative, (data, executable) in sorted(outputs.items()):
        path = out_dir / relative
        if write_generated(path, data, executable=executable,
                           owned=_unchanged_since(path, previous, relative)):
            report.written.append(path)
        else:
            report.unchanged.append(path)
    for relative in sorted(previous.keys() - outputs.keys()):
        path = out_dir / relative
        if not _unchanged_since(path, previous, relative) and \
                not is_generated(path):
            # replaced by a file of the user's since: theirs to keep
            continue
        if remove_generated(path, out_dir):
            report.removed.append(path)
    _write_manifest(manifest_path, final)
    return report


#: The files of a generation -> the digests of the contents it may have
#: written there; None for a manifest written before digests were recorded.
Manifest = dict[str, set[str] | None]


def read_manifest(path: Path) -> Manifest:
    """Return the files a generation wrote, with the digests of each."""
    try:
        lines = path.read_text(encoding='utf-8').split('\n')
    except FileNotFoundError:
        return {}
    files: Manifest = {}
    for line in lines:
        if not line or line.startswith('#'):
            continue
        digest, sep, relative = line.partition('  ')
        if sep and len(digest) == 64:
            files[relative] = (files.get(relative) or set()) | {digest}
        else:
            files[line] = None
    return files


def _write_manifest(path: Path, files: Manifest) -> None:
    write_generated(path, (f'# {GENERATED_NOTE}\n' + ''.join(
        f'{digest}  {relative}\n' for relative in sorted(files)
        for digest in sorted(files[relative] or ())
    )).encode('utf-8'), owned=True)


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _unchanged_since(path: Path, previous: Manifest, relative: str) -> bool:
    """Say whether a file still holds what a generation wrote there."""
    if relative not in previous:
        return False
    digests = previous[relative]
    if digests is None:
        return True  # an old manifest: trust it as before
    try:
        return _digest(path.read_bytes()) in digests
    except OSError:
        return False


GENERATED_NOTE = 'Generated by colcon-robmosys: the files of the last generation'
