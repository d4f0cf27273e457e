"""The installed package: stubs cover the extension with its signatures, docstrings everywhere
public, and the package docstring's examples run."""

import ast
import doctest
import inspect
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


def stub_parameters(function):
    """Names of a stub's parameters, ``*`` before keyword-only ones, without self."""
    args = function.args
    names = [a.arg for a in args.posonlyargs + args.args]
    if args.kwonlyargs:
        names.append("*")
    names += [a.arg for a in args.kwonlyargs]
    return [n for n in names if n not in ("self", "cls")]


def runtime_parameters(obj):
    names, keyword_only = [], False
    for p in inspect.signature(obj).parameters.values():
        if p.kind == p.KEYWORD_ONLY and not keyword_only:
            names.append("*")
            keyword_only = True
        names.append(p.name)
    return [n for n in names if n not in ("self", "cls", "$self", "$cls")]


def test_stub_signatures_match_the_extension():
    tree = ast.parse((PACKAGE / "_angletrack.pyi").read_text())
    checked = 0
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            pairs = [(getattr(_angletrack, node.name), node)]
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            cls = getattr(_angletrack, node.name)
            methods = [f for f in node.body if isinstance(f, ast.FunctionDef)]
            pairs = [
                (cls if f.name == "__init__" else getattr(cls, f.name), f)
                for f in methods
                if "property" not in [ast.unparse(d) for d in f.decorator_list]
                and (f.name == "__init__" or not f.name.startswith("__"))
            ]
        else:
            continue
        for obj, function in pairs:
            assert runtime_parameters(obj) == stub_parameters(function), function.name
            checked += 1
    assert checked > 40


def test_package_docstring_examples_run():
    result = doctest.testmod(angletrack)
    assert result.attempted > 0 and result.failed == 0


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
