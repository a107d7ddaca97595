"""The .pyi stub matches the built extension: every public name, every method, and the
parameter names of every function whose signature the extension exposes."""

import ast
import inspect
from pathlib import Path

import tailor
from tailor import _tailor

STUB = Path(tailor.__file__).with_name("_tailor.pyi")


def stub_tree():
    tree = ast.parse(STUB.read_text())
    classes, functions = {}, {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            members = {}
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    members[item.name] = [a.arg for a in item.args.args + item.args.kwonlyargs]
                elif isinstance(item, ast.AnnAssign):
                    members[item.target.id] = None
            classes[node.name] = members
        elif isinstance(node, ast.FunctionDef):
            functions[node.name] = [a.arg for a in node.args.args + node.args.kwonlyargs]
        elif isinstance(node, ast.AnnAssign) and not node.target.id.startswith("_"):
            functions[node.target.id] = None  # a module constant
    return classes, functions


def public(obj):
    return {n for n in dir(obj) if not n.startswith("_")}


def test_every_module_name_is_stubbed_and_vice_versa():
    classes, functions = stub_tree()
    stubbed = set(classes) | set(functions)
    assert public(_tailor) - stubbed == set(), "missing from the stub"
    assert stubbed - public(_tailor) - {"ArrayLike", "F32", "PathLike"} == set(), "stubbed but not in the module"


def test_class_members_match():
    classes, _ = stub_tree()
    for name, members in classes.items():
        if issubclass(getattr(_tailor, name), BaseException):
            continue
        cls = getattr(_tailor, name)
        assert public(cls) == set(members) - {"__init__"}, name


def test_signatures_match():
    classes, functions = stub_tree()

    def params(f):
        try:
            return [p for p in inspect.signature(f).parameters if p not in ("self", "cls")]
        except (TypeError, ValueError):
            return None

    for name, args in functions.items():
        got = params(getattr(_tailor, name))
        assert got is None or got == args, name
    for cname, members in classes.items():
        cls = getattr(_tailor, cname)
        for mname, args in members.items():
            if args is None or mname == "__init__":
                continue
            got = params(getattr(cls, mname))
            assert got is None or got == [a for a in args if a != "self"], f"{cname}.{mname}"
