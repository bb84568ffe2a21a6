# The type stub (python/hail.pyi) names everything the module has, so IDEs and type checkers
# see the whole API; and help() has a docstring for every public method.
import ast
import pathlib

import hail

STUB = pathlib.Path(__file__).resolve().parents[1] / "hail.pyi"


def stub_names():
    tree = ast.parse(STUB.read_text())
    module, classes = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            module.add(node.name)
            classes[node.name] = {
                (n.target.id if isinstance(n, ast.AnnAssign) else n.name)
                for n in node.body if isinstance(n, (ast.FunctionDef, ast.AnnAssign))
            }
        elif isinstance(node, ast.FunctionDef):
            module.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            module.add(node.target.id)
    return module, classes


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_stub_lists_the_module():
    module, classes = stub_names()
    assert public(hail) <= module | {"ArrayLike"}
    for name in ("World", "Terrain", "TriangleMesh", "VtkFrames", "QueryHit"):
        missing = public(getattr(hail, name)) - classes[name]
        assert not missing, f"{name}: {sorted(missing)} not in hail.pyi"


def test_every_method_has_a_docstring():
    for cls in (hail.World, hail.Terrain, hail.VtkFrames, hail.QueryHit):
        for name in public(cls):
            attr = getattr(cls, name)
            doc = (attr.__doc__ or "").strip()
            # A method's doc starts with pybind11's signature line: it needs a line of its own.
            lines = 1 if isinstance(attr, property) else 2
            assert len(doc.splitlines()) >= lines, f"{cls.__name__}.{name} has no docstring"
