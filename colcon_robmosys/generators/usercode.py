# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The user's files: the implementation checked against the model, the others found.

Also the implementation files of no component of the model, which a rename of
the component leaves behind (:func:`orphan_problems`).
"""

from __future__ import annotations

import os
from pathlib import Path
import re
from typing import Iterable, Iterator, Mapping

from colcon_robmosys.errors import Diagnostic, Location
from colcon_robmosys.generators.files import PackageFiles, UserFile
from colcon_robmosys.generators.render import render

#: What a build leaves among the user's files: never part of the package.
_LEFT_BY_TOOLS = ('__pycache__', '.pytest_cache')


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
    if user_file.check is None:
        return [], False
    return user_file.check(path, text, user_file.required_class,
                           user_file.required_functions,
                           _skeleton_hint(user_file, skeleton))


def user_file_problems(user_file: UserFile, path: Path,
                       skeleton: Path | str = '') -> list[Diagnostic]:
    """Return what the user's code lacks of what the model asks of it."""
    return check_user_file(user_file, path, skeleton)[0]


def user_files_below(folder: Path) -> Iterator[Path]:
    """Yield the user's files below a folder, sorted; none if it is missing.

    Hidden files and what tools leave (``__pycache__``, ``*.pyc``) are not
    the user's sources.
    """
    if not folder.is_dir():
        return
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs
                         if not d.startswith('.') and d not in _LEFT_BY_TOOLS)
        for name in sorted(files):
            if not name.startswith('.') and not name.endswith('.pyc'):
                yield Path(root, name)


def user_tree(package: PackageFiles) -> dict[str, tuple[bytes, bool]]:
    """Return the user's files of a package, at their paths next to the model.

    :returns: path relative to the model's directory -> content, and
      whether it is executable
    """
    found = {}
    for folder in package.user_folders:
        for path in user_files_below(package.model_dir / folder):
            relative = path.relative_to(package.model_dir).as_posix()
            found[relative] = (path.read_bytes(), os.access(path, os.X_OK))
    return found


def merge_conflicts(package: PackageFiles,
                    outputs: Mapping[str, object]) -> list[Diagnostic]:
    """Return an error for each file of the user's that takes a generated name.

    The user's modules are installed with the generated ones, in one Python
    package: one of them would replace the other.
    """
    problems = []
    for folder, generated in package.merged_folders.items():
        for path in user_files_below(package.model_dir / folder):
            relative = path.relative_to(package.model_dir / folder).as_posix()
            if f'{generated}/{relative}' in outputs:
                problems.append(Diagnostic(
                    Location(str(path)),
                    f"the generated module '{generated}/{relative}' has this "
                    'name: rename the file, the package cannot hold both'))
    return problems


#: The name of an implementation file, without its suffix: the class of a
#: component, then ``_impl``.
_IMPL_NAME = re.compile(r'(?P<cls>[A-Za-z_][A-Za-z0-9_]*)_impl')


def implementation_files(folder: Path, suffixes: Iterable[str]) -> list[tuple[str, str]]:
    """Return the implementation files in a folder, of any component: (class, name).

    ``<class>_impl`` with one of the suffixes; none if the folder is missing.
    """
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        return []
    found = []
    for name in names:
        stem, suffix = os.path.splitext(name)
        match = _IMPL_NAME.fullmatch(stem)
        if suffix in suffixes and match:
            found.append((match['cls'], name))
    return found


def orphan_problems(package: PackageFiles) -> list[Diagnostic]:
    """Return one error for the implementation files of no component of the model.

    Renaming a component in the model leaves its implementation files behind:
    C++ compiles them with the package, where they fail on the generated
    header they include, which is gone; Python installs them and never
    imports them. A fresh implementation file made beside them would hide the
    user's code, so the error comes before anything is made or compiled.

    A file counts if it lies where the component's own go, is named
    ``<Name>_impl`` with a suffix of the language and holds what the
    generator made of a component ``<Name>``: the class ``<Name>_impl`` on
    ``<Name>`` (or, for a C++ source without its header, the definitions of
    its functions). A file of the user's that merely ends in ``_impl`` is
    theirs.

    The error is at the component's name in the model, the line a rename
    changed and the one to change back: the message names the files, and
    the rename to make where the model evidently renamed the component.
    """
    impl = package.implementation
    if impl is None:
        return []
    folder = package.model_dir / impl.folder
    groups: dict[str, list[Path]] = {}
    for cls, name in implementation_files(folder, impl.suffixes):
        if cls != impl.component:
            groups.setdefault(cls, []).append(folder / name)
    orphans = {cls: sorted(paths, key=lambda p: impl.suffixes.index(p.suffix))
               for cls, paths in sorted(groups.items())
               if impl.implements(cls, {path: _text(path) for path in paths})}
    if not orphans:
        return []
    paths = [p for group in orphans.values() for p in group]
    it = 'them' if len(paths) > 1 else 'it'
    named = ', '.join(f"'{cls}'" for cls in orphans)
    if len(orphans) == 1:
        message = f'the implementation of a component {named}, which the package ' \
            f"'{package.name}' does not have"
    else:
        message = f'the implementations of components {named}, which the package ' \
            f"'{package.name}' does not have"
    message = f"{', '.join(str(p) for p in paths)}: {message}; "
    new = impl.component
    if len(orphans) == 1 and package.user_files:
        old, group = next(iter(orphans.items()))
        suffixes = [p.suffix for p in group]
        message += f"was '{old}' renamed to '{new}'? "
        own = _own_files(package)
        if own is None:
            message += f'move what you need of {_names(old, suffixes)} into ' \
                f'{_names(new, impl.suffixes)}, then delete {it}'
        else:
            message += f'rename {_names(old, suffixes)} to {_names(new, suffixes)}, ' \
                f"and '{old}' in {it} to '{new}'"
            if own:
                # made by a generation since the rename: nothing of the user's
                message += f' (over {_names(new, own)}, made from the model since)'
    elif package.user_files:
        message += f"the component of '{package.name}' is '{new}': move what you need " \
            f'of {it} into {_names(new, impl.suffixes)}, then delete {it}'
    else:
        message += f"its component '{new}' has no function of the user's: delete {it}"
        if len(orphans) == 1:
            message += f', or name the component {named} again'
    return [Diagnostic(impl.location, message)]


def _text(path: Path) -> str | None:
    """Return the text of a file, None if it cannot be read as UTF-8."""
    try:
        return path.read_text(encoding='utf-8')
    except (OSError, UnicodeDecodeError):
        return None  # not the code the generator made


def _names(cls: str, suffixes: Iterable[str]) -> str:
    """Name the files of a class in short: ``Cls_impl.hpp/.cpp``."""
    return f'{cls}_impl' + '/'.join(suffixes)


def _own_files(package: PackageFiles) -> list[str] | None:
    """Return the component's implementation files that hold nothing of the user's.

    :returns: the suffixes of those there as the generator makes them from the
      model (by ``colcon robmosys-generate``, after a rename); None if any
      holds the user's code
    """
    untouched = []
    for user_file in package.user_files:
        path = package.model_dir / user_file.source_path
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            continue
        except OSError:
            return None
        if data != render(user_file.template, user_file.context).encode('utf-8'):
            return None
        untouched.append(path.suffix)
    return untouched
