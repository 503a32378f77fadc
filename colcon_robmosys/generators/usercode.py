# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""Check the user's implementation files against what the model asks."""

from __future__ import annotations

import ast
from pathlib import Path
import re

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.generators.plan import UserFile


def _skeleton_hint(user_file: UserFile, skeleton: Path | str) -> str:
    """Say where the skeleton that shows what the model asks for lies."""
    where = user_file.skeleton_path
    text = f'the skeleton {where} of the package shows what the model asks for'
    if skeleton:
        text += f': {skeleton}'
    return text


def check_user_file(user_file: UserFile, path: Path, skeleton: Path | str = ''
                    ) -> tuple[list[Diagnostic], bool]:
    """Check that the user's code defines what the model asks of it.

    :param skeleton: where the skeleton that shows what the model asks lies
    :returns: the problems, and whether the skeleton shows how to mend them
      (a class or a function of the model is missing)
    """
    try:
        text = path.read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError) as exc:
        return [Diagnostic(Location(str(path)),
                           f'cannot read the implementation file: {exc}')], False
    if path.suffix in ('.hpp', '.h'):
        problems = _cpp_header_problems(user_file, path, text, skeleton)
    elif path.suffix == '.py':
        try:
            tree = ast.parse(text, filename=str(path))
        except SyntaxError as exc:
            return [Diagnostic(Location(str(path), exc.lineno or 0,
                                        exc.offset or 0),
                               f'Python syntax error: {exc.msg}')], False
        problems = _python_problems(user_file, path, tree, skeleton)
    else:
        problems = []
    return problems, bool(problems)


def user_file_problems(user_file: UserFile, path: Path,
                       skeleton: Path | str = '') -> list[Diagnostic]:
    """Return what the user's code lacks of what the model asks of it."""
    return check_user_file(user_file, path, skeleton)[0]


def _python_problems(user_file: UserFile, path: Path, tree: ast.Module,
                     skeleton_path: Path | str) -> list[Diagnostic]:
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef) and
               n.name == user_file.required_class]
    skeleton = _skeleton_hint(user_file, skeleton_path)
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


def _cpp_header_problems(user_file: UserFile, path: Path, text: str,
                         skeleton_path: Path | str) -> list[Diagnostic]:
    """Check that a C++ header declares the class and functions of the model.

    A compiler would say so too, but only in the middle of the build and in
    terms of pure virtual functions; this names the function of the model.
    Comments, strings and preprocessor lines are blanked out (keeping line
    and column) so that only declarations count.
    """
    code = _CPP_NOISE.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    skeleton = _skeleton_hint(user_file, skeleton_path)
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
