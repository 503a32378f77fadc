# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The Python user's file: the module checked against the model, a component's file known."""

from __future__ import annotations

import ast
from pathlib import Path
import re
from typing import Mapping

from colcon_robmosys.errors import Diagnostic, Location


def module_problems(path: Path, text: str, required_class: str,
                    required_functions: tuple[str, ...],
                    skeleton: str) -> tuple[list[Diagnostic], bool]:
    """Check that a Python module defines the class and methods of the model.

    :param skeleton: where the skeleton that shows what the model asks lies
    :returns: the problems, and whether the skeleton shows how to mend them
      (not for a syntax error)
    """
    try:
        tree = ast.parse(text, filename=str(path))
    except SyntaxError as exc:
        return [Diagnostic(Location(str(path), exc.lineno or 0, exc.offset or 0),
                           f'Python syntax error: {exc.msg}')], False
    classes = [n for n in tree.body if isinstance(n, ast.ClassDef) and
               n.name == required_class]
    if not classes:
        return [Diagnostic(Location(str(path), 1, 1),
                           f"no class '{required_class}' in the "
                           f'implementation file; {skeleton}')], True
    cls = classes[0]
    defined = {n.name for n in cls.body
               if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}
    problems = [Diagnostic(Location(str(path), cls.lineno, cls.col_offset + 1),
                           f"class '{cls.name}' lacks the function '{name}' of "
                           f'the model; {skeleton}')
                for name in required_functions if name not in defined]
    return problems, bool(problems)


def implements(cls: str, texts: Mapping[Path, str | None]) -> bool:
    """Tell whether Python files hold the class ``<cls>_impl`` derived from ``cls``.

    :param texts: the files by path, None where unreadable
    """
    declared = re.compile(rf'^class\s+{re.escape(f"{cls}_impl")}\s*\([^)]*\b{re.escape(cls)}\b',
                          re.MULTILINE)
    return any(text is not None and declared.search(text) for text in texts.values())
