# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The architecture holds: layers import downwards only, modules stay small.

Read from the sources with ast, so that what is tested is what is written
(docs/architecture.md draws the layers).
"""

from __future__ import annotations

import ast
from pathlib import Path
import re

import pytest

REPO = Path(__file__).resolve().parent.parent
PACKAGE = REPO / 'colcon_robmosys'

#: The layers, lowest first: each imports only from those before it.
#: errors.py is the one module every layer shares; report/ writes its
#: diagnostics in the formats of CI tools.
LAYERS = ('errors', 'report', 'model', 'mapping', 'check', 'generators', 'importer')
#: The colcon glue, on top; the only importers of colcon_core.
GLUE = ('package_identification', 'package_discovery', 'package_selection', 'task', 'verb')
#: Tools for developers (tests, benchmarks, the demo): above everything,
#: imported by nothing of the pipeline.
DEVTOOLS = ('devtools',)
#: The robmosys_runtime ament package as package data, and how the glue finds
#: it: by the mapping's name of the package (mapping/common.py) and the one
#: search of install prefixes (check/index.py); imported by the glue only.
RUNTIME = 'runtime'
#: Sources of the ament package inside it: its own Python module, not ours.
RUNTIME_PACKAGE = PACKAGE / RUNTIME / 'robmosys_runtime'

MAX_MODULE_LINES = 350
MAX_TEMPLATE_LINES = 250


def _imports(path: Path) -> set[str]:
    """Return every module a source file imports, absolute names."""
    tree = ast.parse(path.read_text(encoding='utf-8'), filename=str(path))
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.level:
                raise AssertionError(f'{path}: relative import')
            found.add(node.module)
            # `from colcon_robmosys.generators import writer` imports a module
            found.update(f'{node.module}.{alias.name}' for alias in node.names)
    return found


def _subpackage(path: Path) -> str:
    relative = path.relative_to(PACKAGE)
    return relative.parts[0].removesuffix('.py')


def _sources(root: Path) -> list[Path]:
    return sorted(p for p in root.rglob('*.py') if '__pycache__' not in p.parts)


def _package_graph() -> dict[str, set[str]]:
    """Return subpackage (or top-level module) -> those it imports."""
    graph: dict[str, set[str]] = {}
    for path in _sources(PACKAGE):
        if RUNTIME_PACKAGE in path.parents:
            continue
        own = _subpackage(path)
        targets = graph.setdefault(own, set())
        for module in _imports(path):
            parts = module.split('.')
            if parts[0] != 'colcon_robmosys' or len(parts) < 2:
                continue
            if (PACKAGE / parts[1]).is_dir() or \
                    (PACKAGE / f'{parts[1]}.py').is_file():
                targets.add(parts[1])
        targets.discard(own)
    return graph


def test_layers_import_only_downwards():
    graph = _package_graph()
    order = {name: index for index, name in enumerate(LAYERS)}
    problems = []
    for own, targets in sorted(graph.items()):
        if own in GLUE or own in DEVTOOLS or own == '__init__':
            continue
        if own == RUNTIME:
            assert targets <= {'errors', 'mapping', 'check'}, f'runtime imports {targets}'
            continue
        assert own in order, f'{own}: a subpackage of no layer (add it to LAYERS)'
        for target in sorted(targets):
            if target in GLUE or target in DEVTOOLS or \
                    order.get(target, len(LAYERS)) >= order[own]:
                problems.append(f'{own} imports {target}')
    assert problems == []


def test_no_import_cycle_between_subpackages():
    cycles = _cycles(_package_graph())
    assert not cycles, 'import cycles:\n' + '\n'.join(cycles)


def _module_name(path: Path, base: Path = REPO) -> str:
    """Return the dotted name of a source file, importable from base."""
    parts = path.relative_to(base).with_suffix('').parts
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


def _module_graph(sources: list[Path] | None = None,
                  base: Path = REPO) -> dict[str, set[str]]:
    """Return module -> the modules of the same sources it imports, in functions too.

    By default the package's, without the runtime's own. A module counts by
    the name it imports, not by the packages above it that Python runs first
    (``colcon_robmosys.mapping.backends.cpp`` is an edge to that module, not
    to ``colcon_robmosys.mapping.backends``).
    """
    if sources is None:
        sources = [p for p in _sources(PACKAGE) if RUNTIME_PACKAGE not in p.parents]
    paths = {_module_name(p, base): p for p in sources}
    return {name: {m for m in _imports(path) if m in paths and m != name}
            for name, path in paths.items()}


def _cycles(graph: dict[str, set[str]]) -> list[str]:
    """Return a cycle ``a -> b -> a`` for every import that closes one."""
    state: dict[str, int] = {}
    found = []

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for child in sorted(graph.get(node, ())):
            if state.get(child) == 1:
                trail = path + [node]
                found.append(' -> '.join(trail[trail.index(child):] + [child]))
            elif not state.get(child):
                visit(child, path + [node])
        state[node] = 2

    for node in sorted(graph):
        if not state.get(node):
            visit(node, [])
    return found


def test_no_import_cycle_between_modules():
    cycles = _cycles(_module_graph())
    assert not cycles, 'import cycles:\n' + '\n'.join(cycles)


def test_the_cycle_test_finds_what_it_looks_for():
    assert _cycles({'a': {'b'}, 'b': {'c'}, 'c': {'b', 'd'}, 'd': set()}) == ['b -> c -> b']
    assert _cycles({'a': {'a'}}) == ['a -> a']
    graph = _module_graph()
    assert 'colcon_robmosys.generators.writer' in graph['colcon_robmosys.generators']
    # imported in a function, and the package's own __init__.py
    assert 'colcon_robmosys' in graph['colcon_robmosys.report.formats']


def test_pipeline_is_not_importing_glue_or_devtools():
    graph = _package_graph()
    for own in LAYERS:
        assert not graph.get(own, set()) & set(GLUE + DEVTOOLS + (RUNTIME,)), own


def test_only_the_glue_imports_colcon():
    colcon = ('colcon_core', 'colcon_ros', 'colcon_cmake')
    importers = sorted(
        str(path.relative_to(REPO)) for path in _sources(PACKAGE)
        if RUNTIME_PACKAGE not in path.parents and
        any(m.split('.')[0] in colcon for m in _imports(path)))
    assert importers, 'the glue imports colcon_core'
    assert [p for p in importers
            if Path(p).parts[1] not in GLUE] == []


@pytest.mark.parametrize('folder', ['bench', 'tools'])
def test_bench_and_tools_do_not_use_tests(folder: str):
    for path in _sources(REPO / folder):
        text = path.read_text(encoding='utf-8')
        modules = _imports(path)
        assert not {m.split('.')[0] for m in modules} & {'harness', 'conftest', 'tests'}, \
            f'{path.relative_to(REPO)} imports from tests/'
        assert "'tests'" not in text and '"tests"' not in text, \
            f'{path.relative_to(REPO)} puts tests/ on its path'


#: The runtime's Python package (docs/architecture.md, "The runtime's rooms"):
#: its top is the component side, what a component node is made of, which a
#: hand-written node imports and nothing else; each room below it may import
#: the rooms named here, and no other.
RUNTIME_MODULES = RUNTIME_PACKAGE / 'robmosys_runtime'
COMPONENT_SIDE = ''
RUNTIME_ROOMS = {
    COMPONENT_SIDE: set(),
    'tools': {COMPONENT_SIDE},
    'hosting': {COMPONENT_SIDE},
    'watch': {COMPONENT_SIDE, 'hosting'},
    'web': {COMPONENT_SIDE, 'hosting', 'watch'},
    'system': {COMPONENT_SIDE, 'tools', 'hosting', 'watch', 'web'},
}
MAX_FOLDER_MODULES = 15


def _room(module: str) -> str | None:
    """Return the room of a runtime module (or of a name its top exports), else None."""
    parts = module.split('.')
    if parts[0] != 'robmosys_runtime':
        return None
    if len(parts) > 1 and parts[1] in RUNTIME_ROOMS:
        return parts[1]
    return COMPONENT_SIDE


def _runtime_graph() -> dict[str, set[str]]:
    """Return each module of the runtime's Python package -> those of it it imports."""
    return _module_graph(_sources(RUNTIME_MODULES), RUNTIME_PACKAGE)


def test_the_runtime_has_its_rooms():
    found = {_room(name) for name in _runtime_graph()}
    assert found == set(RUNTIME_ROOMS)
    deeper = [name for name in _runtime_graph() if len(name.split('.')) > 3]
    assert deeper == []
    for room in RUNTIME_ROOMS:
        init = RUNTIME_MODULES / room / '__init__.py'
        docstring = ast.get_docstring(ast.parse(init.read_text(encoding='utf-8')))
        assert docstring and 'import' in docstring, f'{init}: say what it holds and imports'


def test_each_room_of_the_runtime_imports_only_the_rooms_below_it():
    problems = []
    for path in _sources(RUNTIME_MODULES):
        own = _room(_module_name(path, RUNTIME_PACKAGE))
        for module in sorted(_imports(path)):
            target = _room(module)
            if target is not None and target != own and target not in RUNTIME_ROOMS[own]:
                problems.append(f'{path.relative_to(REPO)}: {own or "component"} '
                                f'imports {module}')
    assert problems == []


def test_no_module_of_the_runtime_imports_one_of_its_callers():
    """Counting the imports inside functions: each is one the module needs."""
    cycles = _cycles(_runtime_graph())
    assert not cycles, 'import cycles:\n' + '\n'.join(cycles)


def test_hand_written_and_generated_nodes_import_only_the_component_side():
    """A component's code, generated or the user's, needs no room of the runtime."""
    nodes = [*sorted((REPO / 'templates' / 'component_python').glob('*.jinja')),
             *sorted((REPO / 'test_workspace' / 'src').rglob('*.py'))]
    importing = [f'{path.relative_to(REPO)}: {line.strip()}' for path in nodes
                 for line in path.read_text(encoding='utf-8').splitlines()
                 if re.match(r'\s*(from|import) robmosys_runtime', line) and
                 _room(line.split()[1]) != COMPONENT_SIDE]
    assert importing == []
    # what is looked at: the hand-written event server of test_workspace
    assert any('from robmosys_runtime import EventServer' in p.read_text(encoding='utf-8')
               for p in nodes)


def test_no_runtime_folder_holds_more_than_15_modules():
    folders: dict[str, int] = {}
    for path in _sources(RUNTIME_PACKAGE):
        folder = str(path.parent.relative_to(REPO))
        folders[folder] = folders.get(folder, 0) + 1
    assert len(folders) > len(RUNTIME_ROOMS)
    assert {f: n for f, n in folders.items() if n > MAX_FOLDER_MODULES} == {}


def test_modules_are_small():
    big = {str(p.relative_to(REPO)): n for p in _sources(PACKAGE)
           if (n := len(p.read_text(encoding='utf-8').splitlines())) > MAX_MODULE_LINES}
    assert big == {}


def test_templates_are_small():
    big = {}
    for path in sorted((REPO / 'templates').rglob('*.jinja')):
        name = str(path.relative_to(REPO))
        lines = len(path.read_text(encoding='utf-8').splitlines())
        if lines > MAX_TEMPLATE_LINES:
            big[name] = lines
    assert big == {}


#: Where a module may ask which language a component is: the language
#: backends; and the model, where it checks the Python code a model embeds
#: as it builds the model (the model layer imports no backend).
LANGUAGE_BACKENDS = PACKAGE / 'mapping' / 'backends'
LANGUAGE_MODULES = (PACKAGE / 'model' / 'build_components.py',)
#: The names of the languages, as the model spells them.
LANGUAGE_NAMES = frozenset({'cpp', 'python'})


#: Suffixes of the languages' files: a switch on them stands for a language.
LANGUAGE_SUFFIXES = frozenset({'.cpp', '.h', '.hpp', '.py'})


def _language_tests(tree: ast.AST) -> list[int]:
    """Return the lines where code asks for a particular language.

    ``Language.CPP``, a comparison with ``'cpp'`` or ``'python'``, or with a
    suffix of a language's files.
    """
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr in ('CPP', 'PYTHON') and \
                isinstance(node.value, ast.Name) and node.value.id == 'Language':
            lines.append(node.lineno)
        elif isinstance(node, ast.Compare) and any(
                isinstance(o, ast.Constant) and o.value in LANGUAGE_NAMES | LANGUAGE_SUFFIXES
                or isinstance(o, ast.Tuple) and any(
                    isinstance(e, ast.Constant) and e.value in LANGUAGE_SUFFIXES
                    for e in o.elts)
                for o in [node.left, *node.comparators]):
            lines.append(node.lineno)
    return sorted(set(lines))


def test_only_the_backends_ask_for_a_language():
    """A language is one backend (mapping/backends/): nothing else asks for one."""
    asking = [f'{path.relative_to(REPO)}:{line}' for path in _sources(PACKAGE)
              if RUNTIME_PACKAGE not in path.parents and
              LANGUAGE_BACKENDS not in path.parents and path not in LANGUAGE_MODULES
              for line in _language_tests(ast.parse(path.read_text(encoding='utf-8')))]
    assert asking == []


#: A template that compares a value with a language's name.
TEMPLATE_LANGUAGE_TEST = re.compile(r"""(==|!=|\bis)\s*['"](cpp|python)['"]""")


def test_only_the_backends_templates_know_a_language():
    """The shared templates take what differs from the backend's (starter: its fragments)."""
    asking = [f'{path.relative_to(REPO)}:{number}'
              for path in sorted((REPO / 'templates').rglob('*.jinja'))
              if not path.parent.name.startswith('component_')
              for number, line in enumerate(path.read_text(encoding='utf-8').splitlines(), 1)
              if TEMPLATE_LANGUAGE_TEST.search(line)]
    assert asking == []
    assert TEMPLATE_LANGUAGE_TEST.search("{% set python = language == 'python' %}")


def test_the_language_test_finds_what_it_looks_for():
    tree = ast.parse('if component.language is Language.CPP:\n    pass\n'
                     "if outline.language == 'python':\n    pass\n"
                     "x = 'cpp' if compiled else 'python'\n"
                     "if path.suffix in ('.hpp', '.h'):\n    pass\n")
    assert _language_tests(tree) == [1, 3, 6]


#: Where a path docs/architecture.md names may lie: the package's folders are
#: named without ``colcon_robmosys/``, templates at times without ``templates/``.
DOC_ROOTS = (REPO, PACKAGE, REPO / 'templates')
#: Suffixes of the files a document names.
DOC_SUFFIXES = ('.py', '.jinja', '.json', '.md', '.cfg')


def _expand(pattern: str) -> list[str]:
    """Return a path of a document as globs: ``<name>`` is any, ``{a,b}`` either."""
    pattern = re.sub(r'<[^>]+>', '*', pattern)
    match = re.search(r'\{([^}]*)\}', pattern)
    if match is None:
        return [pattern]
    return [expanded for option in match[1].split(',')
            for expanded in _expand(pattern[:match.start()] + option + pattern[match.end():])]


def _named_paths(text: str) -> list[str]:
    """Return what a document names in backquotes that is a path of the repository.

    A name with a slash counts when its first folder is one of the
    repository or the package (``pkg/msg/Name``, ``/diagnostics`` are no
    paths); a file name
    without one when it has a suffix of ours, found anywhere below the
    package or the templates (``graph.py`` of the importer's row).
    """
    found = []
    for name in re.findall(r'`([^`\s]+)`', text):
        first = name.split('/')[0]
        if '/' in name:
            # a ROS name (`/diagnostics`) is no path
            if first and any(glob_exists(root, first) for root in DOC_ROOTS):
                found.append(name)
        elif name.endswith(DOC_SUFFIXES):
            found.append('**/' + name)
    return found


def _missing(named: list[str]) -> list[str]:
    """Return the paths of a document that exist nowhere."""
    return [name for name in named
            if not any(glob_exists(root, name) for root in
                       (DOC_ROOTS[1:] if name.startswith('**/') else DOC_ROOTS))]


def glob_exists(root: Path, pattern: str) -> bool:
    """Tell whether a path pattern of a document matches below a root."""
    return any(next(iter(root.glob(p.rstrip('/'))), None) is not None
               for p in _expand(pattern))


def test_every_path_the_architecture_names_exists():
    text = (REPO / 'docs' / 'architecture.md').read_text(encoding='utf-8')
    named = _named_paths(text)
    assert 'mapping/portkinds.py' in named and '**/graph.py' in named
    assert _missing(named) == []


def test_a_path_of_a_document_is_a_glob():
    assert _expand('generators/{cpp,python}.py') == ['generators/cpp.py', 'generators/python.py']
    assert _expand('templates/component_<language>/') == ['templates/component_*/']
    assert not glob_exists(REPO, 'templates/component_python/ports/<entity>.jinja')
