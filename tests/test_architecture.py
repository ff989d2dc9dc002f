"""The package's layers: every import points down (or sideways within a package), never up,
and no modules import each other in a cycle. Imports inside functions and under
``TYPE_CHECKING`` count too."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "qdsega"

LAYERS = (
    ("qdsega.errors",),
    ("qdsega.atomic", "qdsega.yaml_reader", "qdsega.progress", "qdsega.folder_names", "qdsega.jit"),
    ("qdsega.description",),
    ("qdsega.assembly", "qdsega.obstacle_map"),
    ("qdsega.simulation", "qdsega.workers", "qdsega.task"),
    ("qdsega.agent",),
    ("qdsega.msm",),
    ("qdsega.locomotion",),
    ("qdsega.baselines",),
    ("qdsega.training",),
    ("qdsega.adaptation",),
    ("qdsega.analysis",),
    ("qdsega.driver",),
    ("qdsega.sweep", "qdsega.bench"),
    ("qdsega.match", "qdsega.reform"),
    ("qdsega.commands",),
    ("qdsega.cli",),
    ("qdsega.__main__",),
)
"""Bottom first. A module may import from its own layer's packages and the layers below;
within a layer, only from its own package (``qdsega.sweep`` and ``qdsega.bench`` are
siblings that know nothing of each other, as are ``qdsega.match`` and ``qdsega.reform``)."""

ROOT_IMPORTS = {"qdsega.locomotion"}
"""``import qdsega`` registers the Gymnasium envs, and nothing else."""


def module_name(file: Path) -> str:
    parts = file.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(file: Path) -> set[str]:
    """The qdsega modules ``file`` imports (``from a import b`` counts ``a.b`` where that is a
    module, else ``a``)."""
    found = set()
    for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.split(".")[0] == "qdsega"}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if node.module.split(".")[0] != "qdsega":
                continue
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                found.add(sub if sub in MODULES else node.module)
    return found


MODULES = {module_name(f): f for f in PACKAGE.rglob("*.py")}


def package_of(module: str) -> tuple[int, str]:
    """The layer index and the package (a LAYERS entry) that ``module`` belongs to."""
    for index, layer in enumerate(LAYERS):
        for package in layer:
            if module == package or module.startswith(package + "."):
                return index, package
    raise AssertionError(f"{module} is in no layer: add it to LAYERS")


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    wrong = []
    for module, targets in graph.items():
        if module == "qdsega":
            wrong += [f"qdsega -> {t}" for t in sorted(targets - ROOT_IMPORTS)]
            continue
        layer, package = package_of(module)
        for target in sorted(targets):
            if target == "qdsega":
                if module != "qdsega.cli":
                    wrong.append(f"{module} -> qdsega (the root: import what you need directly)")
                continue
            target_layer, target_package = package_of(target)
            if target_layer > layer or (target_layer == layer and target_package != package):
                wrong.append(f"{module} -> {target}")
    return wrong


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every strongly connected set of two or more modules (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for target in graph.get(node, ()):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def import_graph() -> dict[str, set[str]]:
    graph = {}
    for module, file in MODULES.items():
        graph[module] = {t for t in imports(file) if t != module}
    return graph


def test_every_import_points_down():
    assert upward_imports(import_graph()) == []


def test_no_import_cycle():
    assert cycles(import_graph()) == []


def test_the_checks_catch_a_back_import():
    graph = import_graph()
    graph["qdsega.description.formation"] = {"qdsega.training.run"}
    assert upward_imports(graph) == ["qdsega.description.formation -> qdsega.training.run"]
    graph["qdsega.training.run"] = graph["qdsega.training.run"] | {"qdsega.description.formation"}
    pair = {"qdsega.description.formation", "qdsega.training.run"}
    assert any(pair <= set(component) for component in cycles(graph))
