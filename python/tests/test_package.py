"""The installed package: stubs cover the extension, docstrings everywhere public."""

import ast
import pathlib

import angletrack
from angletrack import _angletrack

PACKAGE = pathlib.Path(angletrack.__file__).parent


def stub_names():
    tree = ast.parse((PACKAGE / "_angletrack.pyi").read_text())
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.ClassDef, ast.FunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return {n for n in names if not n.startswith("_") or n == "__version__"}


def test_stubs_and_py_typed_are_installed_and_match_the_extension():
    assert (PACKAGE / "py.typed").exists()
    public = {n for n in dir(_angletrack) if not n.startswith("_") or n == "__version__"}
    assert stub_names() == public


def test_every_public_class_and_function_has_a_docstring():
    for name in angletrack.__all__:
        obj = getattr(angletrack, name)
        if callable(obj):
            assert obj.__doc__ and obj.__doc__.strip(), name


def test_fault_flags_are_the_cores_bits_by_name():
    members = {name: int(flag) for name, flag in angletrack.Faults.__members__.items()}
    assert members == {
        "LOSS_OF_SIGNAL": 1,
        "DEGRADATION_OF_SIGNAL": 2,
        "LOSS_OF_TRACKING": 4,
        "BAD_SAMPLE": 8,
        "FALSE_LOCK": 16,
        "AMPLITUDE_MISMATCH": 32,
        "OFFSET_OR_QUADRATURE": 64,
    }
