"""The package as a user installs it: every module imports in a fresh interpreter, a built wheel carries its data and
builds the spacecraft model from another folder, and the dependency lists agree (pyproject.toml, requirements.txt
and its lock file)."""

from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from packaging.requirements import Requirement

ROOT = Path(__file__).parents[1]
PACKAGE = ROOT / "lib" / "trusscodesign"
# dotted names under the package: the layer subpackages and their modules
MODULES = sorted(".".join(p.relative_to(PACKAGE).with_suffix("").parts).removesuffix(".__init__")
                 for p in PACKAGE.rglob("*.py") if p.parent != PACKAGE)


def _clean_env() -> dict:
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def test_every_module_imports_in_a_fresh_interpreter(tmp_path: Path) -> None:
    """Each module alone, first in its interpreter (an import cycle or missing data fails at import), run from a
    folder outside the checkout."""
    code = "import importlib, sys; importlib.import_module(sys.argv[1])"
    failed = {}
    for name in ["trusscodesign", *(f"trusscodesign.{m}" for m in MODULES)]:
        run = subprocess.run([sys.executable, "-c", code, name], cwd=tmp_path, capture_output=True, text=True)
        if run.returncode:
            failed[name] = run.stderr.strip().splitlines()[-1]
    assert not failed, failed
    assert len(MODULES) > 25  # the glob found the package


def test_the_docstrings_name_every_module() -> None:
    """The package's docstring names each layer, each layer's docstring each of its modules."""
    import importlib

    import trusscodesign

    layers = [m for m in MODULES if "." not in m]
    assert sorted(layers) == ["control", "infra", "model", "study"]
    assert all(f"``{layer}``" in trusscodesign.__doc__ for layer in layers)
    missing = [m for m in MODULES if "." in m
               and f"``{m.split('.')[1]}``" not in (importlib.import_module(f"trusscodesign.{m.split('.')[0]}").__doc__ or "")]
    assert not missing, f"add them to the module map of their layer's __init__.py: {missing}"


LAYERS = ("infra", "model", "control", "study")  # bottom to top: a module imports its own layer and those below


def _package_imports() -> dict[str, set[str]]:
    """Each module's imports of the package's modules (dotted names under the package, e.g. ``model.ports``), those in
    functions included: a function-level import is a dependency too."""
    graph: dict[str, set[str]] = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        name = ".".join(parts).removesuffix("__init__").rstrip(".")
        here = parts[:-1]  # the module's package, relative to the package's root
        deps = graph.setdefault(name, set())
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = list(here[:len(here) - node.level + 1])
                elif node.module and node.module.split(".")[0] == "trusscodesign":
                    base = []
                else:
                    continue
                mod = (node.module or "").split(".")
                mod = mod[1:] if not node.level else mod
                target = [*base, *[m for m in mod if m]]
                for alias in node.names:  # "from . import ports" imports a module, "from .ports import X" a name
                    sub = ".".join([*target, alias.name])
                    deps.add(sub if (PACKAGE / Path(*sub.split("."))).with_suffix(".py").exists() else ".".join(target))
            elif isinstance(node, ast.Import):
                deps.update(a.name.split(".", 1)[1] for a in node.names if a.name.startswith("trusscodesign."))
        deps.discard("")
        deps.discard(name)
    return graph


def test_imports_go_down_the_layers() -> None:
    """study -> control -> model -> infra: no module imports a layer above its own."""
    up = [f"{m} imports {d}" for m, deps in _package_imports().items() if "." in m
          for d in deps if "." in d and LAYERS.index(d.split(".")[0]) > LAYERS.index(m.split(".")[0])]
    assert not up, up


def test_no_import_cycle() -> None:
    graph = _package_imports()
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(node: str, path: list[str]) -> list[str] | None:
        state[node] = 1
        for dep in sorted(graph.get(node, ())):
            if state.get(dep) == 1:
                return [*path[path.index(dep):], dep] if dep in path else [*path, dep]
            if dep not in state and (cycle := visit(dep, [*path, dep])):
                return cycle
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state and (cycle := visit(start, [start])):
            raise AssertionError(" -> ".join(cycle))


def test_the_dependency_graph_is_read_correctly() -> None:
    """The checks above can fail: known edges are found, and an added upward import would be seen."""
    graph = _package_imports()
    assert {"infra.results", "model.lft"} <= graph["model.spacecraft"]  # a function-level and a top-level import
    assert "control.synthesis" in graph["study.codesign"] and "model.spacecraft" in graph["control.closedloop"]
    assert "model.statespace" in graph["model.lft"] and "model.ports" not in graph["model.lft"]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(out), str(ROOT)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    (path,) = out.glob("trusscodesign-*.whl")
    return path


def test_the_wheel_carries_the_input_data(wheel: Path) -> None:
    names = set(zipfile.ZipFile(wheel).namelist())
    shipped = {str(p.relative_to(ROOT / "lib")) for p in (PACKAGE / "data").rglob("*") if p.is_file()}
    assert shipped and shipped <= names, sorted(shipped - names)
    assert not any(n.startswith(("tests/", "notebooks/", "benchmarks/", "data/")) for n in names)


def test_the_installed_package_builds_the_spacecraft_from_another_folder(wheel: Path, tmp_path: Path) -> None:
    """The wheel unpacked in a folder of its own, first on the path: the open-loop model at h = 2.139 cm has order
    1324, with the data read from the installed copy (not from this checkout)."""
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    work = tmp_path / "elsewhere"
    work.mkdir()
    code = ("import sys; sys.path.insert(0, sys.argv[1]); import trusscodesign; from trusscodesign.infra import paths\n"
            "from trusscodesign.model import spacecraft\n"
            "assert trusscodesign.__file__.startswith(sys.argv[1]), trusscodesign.__file__\n"
            "assert paths.ROOT is None and str(paths.PACKAGE_DATA).startswith(sys.argv[1])\n"
            "print(spacecraft.open_loop(0.02139).G.nstates)")
    run = subprocess.run([sys.executable, "-c", code, str(site)], cwd=work, env=_clean_env(), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
    assert run.stdout.split() == ["1324"]


def _requirements() -> dict[str, Requirement]:
    lines = [line.split("#")[0].strip() for line in (ROOT / "requirements.txt").read_text().splitlines()]
    return {Requirement(line).name.lower(): Requirement(line) for line in lines if line}


def test_pyproject_declares_what_requirements_txt_lists() -> None:
    """The runtime dependencies and the extras of pyproject.toml are requirements.txt's, with the same specifiers."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    declared = [Requirement(r) for r in project["dependencies"]]
    declared += [Requirement(r) for extra in project["optional-dependencies"].values() for r in extra]
    listed = _requirements()
    assert sorted(r.name.lower() for r in declared) == sorted(listed)
    for r in declared:
        assert (r.specifier, r.extras) == (listed[r.name.lower()].specifier, listed[r.name.lower()].extras), r


def test_the_lock_pins_every_requirement_within_its_range() -> None:
    text = (ROOT / "requirements.lock").read_text()
    assert "uv pip compile requirements.txt -o requirements.lock" in text.splitlines()[1]  # how to regenerate it
    pins = dict(re.findall(r"^([A-Za-z0-9_.\-]+)==(\S+)", text, flags=re.M))
    pins = {re.sub(r"[-_.]+", "-", k).lower(): v for k, v in pins.items()}
    for name, req in _requirements().items():
        key = re.sub(r"[-_.]+", "-", name)
        assert key in pins, f"{name} is not in requirements.lock: regenerate it (command at its top)"
        assert req.specifier.contains(pins[key]), f"{name}=={pins[key]} in the lock is outside {req.specifier}"


def test_requires_python_admits_the_locked_python() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    lock_python = re.search(r"--python-version (\S+)", (ROOT / "requirements.lock").read_text()).group(1)
    assert Requirement(f"python{project['requires-python']}").specifier.contains(f"{lock_python}.0")
