"""The type stubs (chromatag/__init__.pyi) and the docstrings against the module
itself: every public name, member and parameter the module has is in the stubs
with the same name, nothing the module lacks is, every public name says what
it is, and the simple types the stubs promise are the ones a real detection
carries."""
import ast
import inspect
import os
import re

import numpy as np

import chromatag

STUB = os.path.join(os.path.dirname(chromatag.__file__), "__init__.pyi")


def stub_tree():
    with open(STUB) as f:
        return ast.parse(f.read())


def split_top_level(text):
    """Splits at commas outside brackets and quotes."""
    parts, depth, quote, current = [], 0, None, ""
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
            continue
        current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def runtime_parameters(function):
    """Parameter names (without self), '*' for a keyword-only marker and '**'
    for **kwargs, from pybind11's signature line or from inspect."""
    doc = (function.__doc__ or "").split("\n")[0]
    match = re.match(r"^\w+\((.*)\) -> .*$", doc)
    if match:
        names = []
        for part in split_top_level(match.group(1)):
            if part == "*":
                names.append("*")
            elif part.startswith("**"):
                names.append("**")
            else:
                names.append(part.split(":")[0].split("=")[0].strip())
        return [n for n in names if n != "self"]
    names = []
    for p in inspect.signature(function).parameters.values():
        if p.kind == p.VAR_KEYWORD:
            names.append("**")
            continue
        if p.kind == p.KEYWORD_ONLY and "*" not in names:
            names.append("*")
        names.append(p.name)
    return [n for n in names if n != "self"]


def stub_parameters(node):
    a = node.args
    names = [p.arg for p in a.posonlyargs + a.args]
    if a.kwonlyargs:
        names.append("*")
        names += [p.arg for p in a.kwonlyargs]
    if a.kwarg:
        names.append("**")
    return [n for n in names if n != "self"]


def is_property(node):
    return any(isinstance(d, ast.Name) and d.id == "property" for d in node.decorator_list)


def summary(doc, name):
    """A docstring's text without pybind11's signature line."""
    lines = [l for l in (doc or "").split("\n") if l.strip()]
    if lines and re.match(r"^" + re.escape(name) + r"\(.*\) -> ", lines[0]):
        lines = lines[1:]
    return " ".join(lines)


def test_stubs_name_exactly_the_public_names():
    tree = stub_tree()
    defined = {n.name for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    annotated = {n.target.id for n in tree.body if isinstance(n, ast.AnnAssign)}
    public = set(chromatag.__all__)
    assert defined | (annotated & public) == public
    for name in public:
        assert hasattr(chromatag, name), name


def test_stubs_match_every_class_member_and_parameter():
    tree = stub_tree()
    checked = 0
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            assert stub_parameters(node) == runtime_parameters(getattr(chromatag, node.name)), node.name
            checked += 1
            continue
        if not isinstance(node, ast.ClassDef):
            continue
        cls = getattr(chromatag, node.name)
        members = {}
        for item in node.body:
            if isinstance(item, ast.FunctionDef):
                members.setdefault(item.name, []).append(item)
        runtime = {name for name in vars(cls)
                   if not name.startswith("_") or name in ("__init__", "__len__", "__eq__", "__hash__")}
        if issubclass(cls, Exception):
            runtime = set()
        # pybind11 gives every class an __init__ (raising for those Python cannot build).
        if "__init__" in runtime and "__init__" not in members:
            try:
                cls()
            except TypeError as e:
                assert "No constructor defined" in str(e), (node.name, e)
                runtime.discard("__init__")
        assert set(members) == runtime, (node.name, set(members) ^ runtime)
        for name, defs in members.items():
            value = vars(cls)[name]
            if is_property(defs[0]):
                assert isinstance(value, property), (node.name, name)
                continue
            if name in ("__eq__", "__hash__", "__len__"):
                continue
            if node.name == "Detector" and name == "__init__":
                # families, then keywords: the stub's must be the ones the docstring names.
                assert runtime_parameters(value) == ["families", "**"]
                doc = cls.__doc__
                for keyword in stub_parameters(defs[0]):
                    if keyword not in ("*", "**", "families"):
                        assert keyword + "=" in doc, keyword
                continue
            function = value.__func__ if isinstance(value, staticmethod) else value
            # Every overload names the same parameters as the module.
            for d in defs:
                assert stub_parameters(d) == runtime_parameters(function), (node.name, name)
            checked += 1
    assert checked >= 15


def test_every_public_name_has_a_docstring():
    missing = []
    assert summary(chromatag.__doc__, "chromatag")
    for name in chromatag.__all__:
        if name == "__version__":
            continue
        obj = getattr(chromatag, name)
        if not summary(obj.__doc__, name):
            missing.append(name)
        if not inspect.isclass(obj):
            continue
        for attr, value in vars(obj).items():
            if attr.startswith("_"):
                continue
            doc = value.__doc__ if not isinstance(value, staticmethod) else value.__func__.__doc__
            if not summary(doc, attr):
                missing.append(name + "." + attr)
    assert missing == []


def test_a_real_detection_has_the_types_the_stubs_promise():
    tag = chromatag.render_tag("16h5", 3, 12)
    frame = np.full((300, 300, 3), 128, np.uint8)
    frame[40:40 + tag.shape[0], 50:50 + tag.shape[1]] = tag
    k = np.array([[500.0, 0, 150], [0, 500.0, 150], [0, 0, 1]])
    detector = chromatag.Detector(camera_matrix=k, tag_size=0.04)
    (d,) = detector.detect(frame)
    simple = {"int": int, "float": float, "str": str, "bool": bool}
    tree = stub_tree()
    for node in tree.body:
        if not isinstance(node, ast.ClassDef) or node.name not in ("Detection", "Pose"):
            continue
        obj = d if node.name == "Detection" else d.pose
        for item in node.body:
            if isinstance(item, ast.FunctionDef) and is_property(item):
                value = getattr(obj, item.name)
                annotation = ast.unparse(item.returns)
                if annotation in simple:
                    assert isinstance(value, simple[annotation]), (item.name, type(value))
                elif annotation == "_Float":
                    assert isinstance(value, np.ndarray) and value.dtype == np.float64, item.name
                elif annotation == "Tuple[float, float]":
                    assert isinstance(value, tuple) and len(value) == 2, item.name
    assert isinstance(d.as_dict(), dict)
    detections, rejected = detector.detect(frame, "bgr", True)
    assert isinstance(detections, list) and isinstance(rejected, list)


def test_help_lists_every_class_with_its_documentation():
    import pydoc

    text = pydoc.render_doc(chromatag, renderer=pydoc.plaintext)
    for name in ("Board", "BoardPose", "BoardTag", "Detection", "Detector", "Error", "Pose",
                 "SheetVerdict", "TagVerdict"):
        assert f"class {name}" in text, name
    assert "how clearly the two shades split" in text  # Detection.decision_margin's docstring.
