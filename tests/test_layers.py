"""Layers that point one way (issue 22 item 3) and a cheap ``import isotween`` (issue 21 item 1).

The module-level imports of every module of ``src/isotween`` are read with
``ast`` (imports inside functions and under ``if TYPE_CHECKING:`` are made at
call time or never, so they do not count); the graph they form among package
modules must have no cycle, and the model modules must import nothing above the
model. A fresh interpreter then checks what ``import isotween`` loads.
"""

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

import isotween

PACKAGE = Path(isotween.__file__).parent

#: the model: what every layer may import, and what imports no other layer (the option checks of
#: `_validate` sit beside the errors)
MODEL = {"isotween.shape", "isotween.sequence", "isotween.paint", "isotween.times", "isotween.errors",
         "isotween._validate"}

#: what ``import isotween`` may load: the package, the model and the modules of lazy public names' bookkeeping
ALLOWED_AT_IMPORT = {"isotween"} | MODEL

#: third-party modules that ``import isotween`` must not load
HEAVY = ("scipy.optimize", "scipy.sparse", "scipy.interpolate", "matplotlib", "shapely", "svgelements", "numba",
         "PIL", "click", "tqdm")


def _module_name(path):
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_type_checking(test):
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _module_level_imports(tree):
    """Import nodes run when the module is imported: not in functions or ``if TYPE_CHECKING:`` blocks."""
    todo = list(tree.body)
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        elif isinstance(node, ast.If):
            if not _is_type_checking(node.test):
                todo += node.body
            todo += node.orelse
        elif isinstance(node, (ast.Try, ast.With, ast.ClassDef)):
            for name in ("body", "orelse", "finalbody", "handlers"):
                for child in getattr(node, name, ()):
                    todo += child.body if isinstance(child, ast.ExceptHandler) else [child]


def import_graph():
    """``{module: set of package modules it imports at module level}`` for every module of the package."""
    paths = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    modules = set(paths)
    graph = {}
    for name, path in paths.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in _module_level_imports(ast.parse(path.read_text(encoding="utf-8"))):
            names_from = set()  # packages whose __init__ must have run far enough to define a name
            if isinstance(node, ast.Import):
                candidates = [alias.name for alias in node.names]
            else:
                base = package.split(".")
                if node.level:
                    base = base[: len(base) - node.level + 1]
                    base = base + node.module.split(".") if node.module else base
                else:
                    base = node.module.split(".")
                base_name = ".".join(base)
                # `from pkg import sub` imports the submodule; `from mod import name` only the module
                candidates = [f"{base_name}.{alias.name}" if f"{base_name}.{alias.name}" in modules else base_name
                              for alias in node.names]
                if base_name in candidates:
                    names_from.add(base_name)
            for target in candidates:
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                # an ancestor package is imported before its modules, but a name taken from its
                # __init__ while that __init__ imports this module is a circle too
                if target and target != name and (target in names_from or not name.startswith(target + ".")):
                    targets.add(target)
                    # importing a submodule runs its parent packages' __init__ first
                    parent = target.rpartition(".")[0]
                    while parent and parent != name:
                        if not name.startswith(parent + "."):
                            targets.add(parent)
                        parent = parent.rpartition(".")[0]
        graph[name] = targets
    return graph


def find_cycle(graph):
    """One import cycle as a list of modules (first repeated at the end), or None."""
    state = {}
    stack = []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                cycle = visit(nxt)
                if cycle:
                    return cycle
        state[node] = "done"
        stack.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def test_graph_sees_imports():
    graph = import_graph()
    assert "isotween.shape" in graph["isotween.sequence"]
    assert "isotween.errors" in graph["isotween.shape"]
    assert len(graph) > 50


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


@pytest.mark.parametrize("module", sorted(MODEL))
def test_model_imports_only_the_model(module):
    above = import_graph()[module] - MODEL
    assert not above, f"{module} imports {sorted(above)} at module level; import them inside the method that needs them"


def test_import_isotween_loads_only_the_model():
    code = ("import isotween, json, sys; print(json.dumps(sorted(m for m in sys.modules "
            "if m.startswith('isotween') or m.split('.')[0] in ('scipy', 'matplotlib', 'shapely', "
            "'svgelements', 'numba', 'PIL', 'click', 'tqdm'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    loaded = json.loads(out.stdout)
    ours = {m for m in loaded if m.startswith("isotween")}
    assert ours <= ALLOWED_AT_IMPORT, f"import isotween loads {sorted(ours - ALLOWED_AT_IMPORT)}"
    heavy = [m for m in loaded if m in HEAVY or m.startswith(tuple(h + "." for h in HEAVY))]
    assert not heavy, f"import isotween loads {heavy}"


def test_public_names_resolve():
    for name in isotween.__all__:
        assert getattr(isotween, name) is not None, name
    assert set(isotween.__all__) <= set(dir(isotween))


#: layers above the readers and writers of `isotween.io`
IO_MUST_NOT_IMPORT = ("isotween.correspondence", "isotween.optimisation", "isotween.render", "isotween.cli",
                      "isotween.baselines", "isotween.foldfree", "isotween.outputs", "isotween.batch",
                      "isotween.interpolate")


def test_readers_and_writers_import_no_layer_above():
    graph = import_graph()
    for module, targets in graph.items():
        if module.startswith("isotween.io"):
            above = sorted(t for t in targets if t.startswith(IO_MUST_NOT_IMPORT))
            assert not above, f"{module} imports {above} at module level"
        if module.startswith("isotween.render"):
            above = sorted(t for t in targets if t.startswith(("isotween.cli", "isotween.batch")))
            assert not above, f"{module} imports {above} at module level"


def _loaded_after(code):
    """Modules of isotween and heavy libraries loaded by ``code`` in a fresh interpreter."""
    probe = (f"import json, sys\ntry:\n    {code}\nexcept SystemExit:\n    pass\n"
             "print(json.dumps(sorted(m for m in sys.modules if m.startswith('isotween') or m.split('.')[0] in "
             "('scipy', 'matplotlib', 'shapely', 'svgelements', 'numba', 'PIL'))), file=sys.stderr)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return set(json.loads(out.stderr.strip().splitlines()[-1]))


def test_cli_help_loads_no_command():
    loaded = _loaded_after("from isotween.cli import main; main(['--help'])")
    commands = sorted(m for m in loaded if m.startswith("isotween.cli."))
    assert not commands, f"isotween --help imports {commands}"
    heavy = sorted(m for m in loaded if m in HEAVY or m.startswith(tuple(h + "." for h in HEAVY)))
    assert not heavy, f"isotween --help imports {heavy}"


def test_cli_command_loads_only_its_module():
    loaded = _loaded_after("from isotween.cli import main; main(['interpolate', '--help'])")
    assert "isotween.cli.interpolate" in loaded
    others = sorted(m for m in loaded if m.startswith("isotween.cli.") and m.rpartition(".")[2] in
                    ("batch", "compare", "demo", "edit", "info", "keyframes", "render", "transfer"))
    assert not others, f"isotween interpolate imports {others}"
    assert not {"matplotlib", "svgelements", "numba", "PIL"} & loaded


@pytest.mark.parametrize("name", ["out.npz", "out.svg", "out.css", "out.waapi.json", "out.lottie.json", "out.html"])
def test_cli_interpolate_of_an_icon_pair_loads_no_more_than_it_needs(tmp_path, name):
    """A sequence file and the web outputs (text, the page) load no plotting library, no image library, no numba."""
    pytest.importorskip("shapely")
    svg = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">{}</svg>'
    a, b, out = tmp_path / "a.svg", tmp_path / "b.svg", tmp_path / name
    a.write_text(svg.format('<path d="M2 0a2 2 0 0 0-2 2v12a2 2 0 0 0 2 2h12a2 2 0 0 0 2-2V2a2 2 0 0 0-2-2H2z"/>'))
    b.write_text(svg.format('<circle cx="8" cy="8" r="8"/>'))
    loaded = _loaded_after(f"from isotween.cli import main; main(['interpolate', {str(a)!r}, {str(b)!r}, "
                           f"'-o', {str(out)!r}, '-q'])")
    assert out.exists()
    spare = sorted(m for m in loaded if m.startswith(("scipy.spatial", "scipy.special", "scipy.optimize",
                                                      "matplotlib", "PIL", "numba")))
    assert not spare, f"isotween interpolate a.svg b.svg -o {name} imports {spare}"


def test_cli_render_loads_no_solver():
    loaded = _loaded_after("from isotween.cli import main; main(['render', '--help'])")
    solver = sorted(m for m in loaded if m.startswith(("isotween.optimisation", "isotween.interpolate",
                                                       "isotween.baselines", "isotween.foldfree", "scipy.sparse.linalg",
                                                       "numba")))
    assert not solver, f"isotween render imports {solver}"


def test_cli_summaries_match_the_commands():
    import click.utils

    from isotween.cli import COMMANDS, main

    ctx = click.Context(main)
    assert main.list_commands(ctx) == sorted(COMMANDS)
    for name, summary in COMMANDS.items():
        command = main.get_command(ctx, name)
        for limit in (45, 80, 1000):
            assert command.get_short_help_str(limit) == click.utils.make_default_short_help(summary, limit), name


@pytest.mark.parametrize("name", ["batch", "compare", "interpolate", "transfer"])
def test_modules_are_not_shadowed_by_their_functions(name):
    import importlib
    import types

    module = importlib.import_module(f"isotween.{name}")
    assert isinstance(module, types.ModuleType) and getattr(isotween, name) is module
    assert callable(module) and callable(getattr(module, name))
    out = subprocess.run([sys.executable, "-c", f"import isotween.{name} as m, types; "
                          "print(isinstance(m, types.ModuleType))"], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"
