"""The package itself: its stubs describe exactly what the extension exports, and everything has a docstring."""
import ast
from pathlib import Path

import lodforge
from lodforge import _core


def stub_names():
    tree = ast.parse((Path(lodforge.__file__).parent / "_core.pyi").read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names


def test_stubs_match_the_extension():
    exported = {n for n in dir(_core) if not n.startswith("__") or n == "__version__"}
    stubbed = stub_names()
    if not lodforge.HAVE_RENDER:
        stubbed.discard("render_compare")
    assert exported == stubbed


def test_the_package_exports_everything_with_docs():
    assert set(lodforge.__all__) <= set(dir(lodforge))
    for name in lodforge.__all__:
        obj = getattr(lodforge, name)
        if callable(obj):
            assert (obj.__doc__ or "").strip(), f"{name} has no docstring"
    assert lodforge.Error.__module__ == "lodforge" and issubclass(lodforge.Cancelled, lodforge.Error)
    assert lodforge.__version__.count(".") == 2
