# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The C++ user's files: the header checked against the model, a component's files known."""

from __future__ import annotations

from pathlib import Path
import re
from typing import Mapping

from colcon_robmosys.errors import Diagnostic, Location

#: C++ comments, string and character literals, and preprocessor lines.
_CPP_NOISE = re.compile(
    r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'|^[ \t]*#[^\n]*',
    re.DOTALL | re.MULTILINE)


def header_problems(path: Path, text: str, required_class: str,
                    required_functions: tuple[str, ...],
                    skeleton: str) -> tuple[list[Diagnostic], bool]:
    """Check that a C++ header declares the class and functions of the model.

    A compiler would say so too, but only in the middle of the build and in
    terms of pure virtual functions; this names the function of the model.
    Comments, strings and preprocessor lines are blanked out (keeping line
    and column) so that only declarations count.

    :param skeleton: where the skeleton that shows what the model asks lies
    """
    code = _CPP_NOISE.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    cls = re.search(rf'\b(?:class|struct)\s+{re.escape(required_class)}\b'
                    r'[^;{]*\{', code)
    if cls is None:
        return [Diagnostic(Location(str(path), 1, 1),
                           f"no class '{required_class}' in the "
                           f'implementation file; {skeleton}')], True
    line = code.count('\n', 0, cls.start()) + 1
    column = cls.start() - code.rfind('\n', 0, cls.start())
    body = code[cls.end():]
    problems = [Diagnostic(Location(str(path), line, column),
                           f"class '{required_class}' lacks the function "
                           f"'{name}' of the model; {skeleton}")
                for name in required_functions
                if not re.search(rf'\b{re.escape(name)}\s*\(', body)]
    return problems, bool(problems)


def implements(cls: str, texts: Mapping[Path, str | None]) -> bool:
    """Tell whether C++ files hold the implementation of a component ``cls``.

    The class ``<cls>_impl`` derived from ``cls``, or, for a source without
    its header, the definitions of its functions.

    :param texts: the files by path, None where unreadable
    """
    suffixes = {p.suffix for p in texts}
    name = re.escape(f'{cls}_impl')
    for path, text in texts.items():
        if text is None:
            continue
        code = _CPP_NOISE.sub(' ', text)
        found = re.search(rf'\b(?:class|struct)\s+{name}\b[^;{{]*:[^;{{]*'
                          rf'\b{re.escape(cls)}\b', code)
        if found is None and path.suffix == '.cpp' and '.hpp' not in suffixes:
            found = re.search(rf'\b{name}\s*::', code)
        if found:
            return True
    return False
