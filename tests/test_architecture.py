"""The house's rules, read from the source (ast, nothing imported): no import circle inside a
package, arrows between packages point one way (cubot_cad -> structure_fem -> swarm_sim ->
voidcross), and inside a package a sub-package imports only from its own layer or a lower one
(docs/architecture.md). Every import counts: module level, inside functions, under
TYPE_CHECKING."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("cubot_cad", "structure_fem", "swarm_sim", "voidcross")
#: A package may import the packages before it, never those after it.
ORDER = {p: i for i, p in enumerate(PACKAGES)}
#: Heavy dependencies swarm_sim must import without (the brief: it runs where no CAD or FE is installed).
NOT_IN_SWARM_SIM = ("cadquery", "OCP", "exudyn", "gmsh", "skfem")
#: The layers inside each package, lowest first: a sub-package (folder) or a top-level module
#: imports only from its own layer or a lower one. The root ``__init__`` (a facade of
#: re-exports) is exempt; every other module must be placed.
LAYERS = {
    "cubot_cad": [
        {"errors", "atomic", "jsonrecord", "shapes", "part", "properties", "settings", "mesh", "manifest"},
        {"hardware"}, {"couplings"}, {"robots"}, {"checks"}, {"piers"}, {"outputs"},
    ],
    "structure_fem": [
        {"errors", "limits", "solve_cache"}, {"couplings"}, {"model"}, {"analysis"}, {"outputs"},
    ],
    "swarm_sim": [
        {"errors", "state", "params", "tunables", "faults"}, {"engine"}, {"behaviour"},
        {"resolve", "step", "compiled", "invariants", "render", "runner", "decision_docs"},
        {"experiments", "sweeps"}, {"optimise"},
    ],
}


def module_files(root: Path, package: str) -> dict[str, tuple[Path, bool]]:
    """``{dotted module name: (file, is a package __init__)}`` for every module of ``package``."""
    out = {}
    for f in sorted((root / package).rglob("*.py")):
        parts = list(f.relative_to(root).with_suffix("").parts)
        is_pkg = parts[-1] == "__init__"
        out[".".join(parts[:-1] if is_pkg else parts)] = (f, is_pkg)
    return out


def _owner(name: str, mods) -> str | None:
    while name and name not in mods:
        name = name.rpartition(".")[0]
    return name or None


def _through_init(target: str, attr: str, mods, depth: int = 0) -> str:
    """A name imported from a package's ``__init__`` that the ``__init__`` re-exports from one of
    its modules is an arrow to that module (an ``__init__`` that only re-exports is no hub)."""
    f, is_pkg = mods[target]
    if not is_pkg or depth > 8:
        return target
    for node in ast.parse(f.read_text()).body:
        if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module:
            if any((a.asname or a.name) == attr for a in node.names) and f"{target}.{node.module}" in mods:
                return _through_init(f"{target}.{node.module}", attr, mods, depth + 1)
    return target


def imports(name: str, file: Path, is_pkg: bool, mods) -> list[tuple[str, int]]:
    """(imported module, line) for every import in ``file`` that names a module in ``mods`` or
    another package of the project (then the arrow names the other package's module)."""
    here = name.split(".") if is_pkg else name.split(".")[:-1]
    out = []
    for node in ast.walk(ast.parse(file.read_text())):
        if isinstance(node, ast.Import):
            out += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            for a in node.names:
                sub = f"{target}.{a.name}"
                if sub in mods:
                    out.append((sub, node.lineno))
                elif target in mods:
                    out.append((_through_init(target, a.name, mods), node.lineno))
                else:
                    out.append((target, node.lineno))
    return out


def graph(root: Path, package: str) -> dict[str, list[tuple[str, int]]]:
    """Arrows between the modules of ``package``: ``{module: [(module it imports, line)]}``."""
    mods = module_files(root, package)
    g = {}
    for m, (f, is_pkg) in mods.items():
        g[m] = sorted({(o, line) for t, line in imports(m, f, is_pkg, mods) if (o := _owner(t, mods)) and o != m})
    return g


def circles(g: dict[str, list[tuple[str, int]]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w, _line in g.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def _describe(g, comp) -> str:
    inside = set(comp)
    return "; ".join(f"{m} -> {', '.join(sorted({t for t, _ in g[m] if t in inside}))}" for m in comp)


@pytest.mark.parametrize("package", PACKAGES)
def test_no_package_has_an_import_circle(package):
    g = graph(ROOT, package)
    found = circles(g)
    assert not found, "import circles: " + " | ".join(_describe(g, c) for c in found)


@pytest.mark.parametrize("package", PACKAGES)
def test_arrows_between_packages_point_one_way(package):
    upward = []
    mods = module_files(ROOT, package)
    for m, (f, is_pkg) in mods.items():
        for target, line in imports(m, f, is_pkg, mods):
            top = target.split(".")[0]
            if top in ORDER and ORDER[top] > ORDER[package]:
                upward.append(f"{f.relative_to(ROOT)}:{line} imports {target}")
    assert not upward, "upward arrows: " + "; ".join(upward)


def test_swarm_sim_names_no_cad_or_fe_library():
    mods = module_files(ROOT, "swarm_sim")
    bad = [f"{f.relative_to(ROOT)}:{line} imports {t}" for m, (f, p) in mods.items()
           for t, line in imports(m, f, p, mods) if t.split(".")[0] in NOT_IN_SWARM_SIM]
    assert not bad, "; ".join(bad)


def layer_of(module: str, package: str) -> int | None:
    """The layer of ``module`` (its first name below ``package``); None for the root ``__init__``."""
    rest = module[len(package) + 1:].split(".")[0] if module != package else None
    if rest is None:
        return None
    for i, names in enumerate(LAYERS[package]):
        if rest in names:
            return i
    raise AssertionError(f"{module} is in no layer of tests/test_architecture.py LAYERS[{package!r}]: "
                         "place it (and say so in docs/architecture.md)")


def upward_arrows(g: dict, package: str) -> list[str]:
    out = []
    for m, arrows in g.items():
        lm = layer_of(m, package)
        if lm is None:
            continue
        for t, line in arrows:
            lt = layer_of(t, package)
            if lt is not None and lt > lm:
                out.append(f"{m}:{line} imports {t} (layer {lm} -> {lt})")
    return out


@pytest.mark.parametrize("package", sorted(LAYERS))
def test_inside_a_package_arrows_point_down_the_layers(package):
    bad = upward_arrows(graph(ROOT, package), package)
    assert not bad, "upward arrows between sub-packages: " + "; ".join(bad)


@pytest.mark.parametrize("package", sorted(LAYERS))
def test_every_sub_package_says_what_lives_there_and_what_it_may_import(package):
    for init in sorted((ROOT / package).glob("*/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text())) or ""
        assert len(doc.strip().splitlines()) >= 2 and "may import" in doc.lower(), \
            f"{init.relative_to(ROOT)}: a docstring of two lines, what lives here and what it may import"


# -- the checker checks: it finds what it is for ------------------------------------------------

def _write(root: Path, files: dict[str, str]) -> None:
    for rel, text in files.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)


def test_the_checker_finds_a_circle_through_a_lazy_import_and_a_reexport(tmp_path):
    _write(tmp_path, {
        "pkg/__init__.py": "from .a import A\n",
        "pkg/a.py": "def A():\n    from .b import B\n    return B\n",
        "pkg/b.py": "from pkg import A\nB = 1\n",
        "pkg/c.py": "from . import a\n",
    })
    g = graph(tmp_path, "pkg")
    assert circles(g) == [["pkg.a", "pkg.b"]]  # b -> a through the __init__'s re-export


def test_the_checker_passes_a_one_way_tree(tmp_path):
    _write(tmp_path, {
        "pkg/__init__.py": "",
        "pkg/low.py": "X = 1\n",
        "pkg/sub/__init__.py": "",
        "pkg/sub/high.py": "from ..low import X\nfrom pkg.sub import mid\n",
        "pkg/sub/mid.py": "import pkg.low\n",
    })
    g = graph(tmp_path, "pkg")
    assert circles(g) == []
    assert ("pkg.low", 1) in g["pkg.sub.high"] and ("pkg.sub.mid", 2) in g["pkg.sub.high"]


def test_the_checker_finds_an_arrow_up_the_layers(tmp_path, monkeypatch):
    _write(tmp_path, {
        "cubot_cad/__init__.py": "",
        "cubot_cad/part.py": "from cubot_cad.robots.base import Robot\n",  # core -> robots: up
        "cubot_cad/robots/__init__.py": "",
        "cubot_cad/robots/base.py": "from cubot_cad.part import x\n",
    })
    g = graph(tmp_path, "cubot_cad")
    assert upward_arrows(g, "cubot_cad") == ["cubot_cad.part:1 imports cubot_cad.robots.base (layer 0 -> 3)"]
    _write(tmp_path, {"cubot_cad/stray.py": ""})
    with pytest.raises(AssertionError, match="stray is in no layer"):
        upward_arrows(graph(tmp_path, "cubot_cad"), "cubot_cad")
