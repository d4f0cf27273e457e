"""The installed package: stubs cover the extension with its signatures, docstrings everywhere
public, and the package docstring's examples run."""

import ast
import doctest
import inspect
import pathlib

import numpy as np

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


def test_estimates_stubs_type_as_optional_exactly_what_a_batch_may_leave_out():
    tree = ast.parse((PACKAGE / "_angletrack.pyi").read_text())
    classes = {node.name: node for node in tree.body if isinstance(node, ast.ClassDef)}

    def property_types(name):
        return {
            f.name: ast.unparse(f.returns)
            for f in classes[name].body
            if isinstance(f, ast.FunctionDef) and "property" in [ast.unparse(d) for d in f.decorator_list]
        }

    gains = angletrack.Gains([0.1, 0.005], 1e-4)
    samples = np.array([[1.0, 0.9], [0.0, 0.1]])
    left_out = angletrack.track_batch(gains, samples, samples, outputs=())
    may_be_none = {name for name in property_types("Estimates") if getattr(left_out, name) is None}
    assert may_be_none == {"angle", "position", "speed", "acceleration", "phase_error", "faults"}
    selected, full = property_types("_SelectedEstimates"), property_types("Estimates")
    assert {name for name, t in selected.items() if t.startswith("Optional[")} == may_be_none
    assert not any(t.startswith("Optional[") for t in full.values())
    assert all(full[name] == selected[name][len("Optional["):-1] for name in may_be_none)
    everything = angletrack.track_batch(gains, samples, samples)
    assert all(getattr(everything, name) is not None for name in may_be_none)
    # A batch call returns `Estimates` when `outputs` is left out (None), else `_SelectedEstimates`.
    batch_calls = [f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "track_batch"]
    batch_calls += [f for f in classes["ObserverBatch"].body if isinstance(f, ast.FunctionDef) and f.name == "update"]
    returns = {
        (f.name, ast.unparse(next(a.annotation for a in f.args.kwonlyargs if a.arg == "outputs"))): ast.unparse(f.returns)
        for f in batch_calls
    }
    assert returns == {
        ("track_batch", "None"): "Estimates",
        ("track_batch", "_Outputs"): "_SelectedEstimates",
        ("update", "None"): "Estimates",
        ("update", "_Outputs"): "_SelectedEstimates",
    }


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
        "FRONT_END": 128,
    }
