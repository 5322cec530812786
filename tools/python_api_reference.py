#!/usr/bin/env python3
"""Writes docs/python-api.md, the Python API reference, from the package's docstrings.

    tools/python_api_reference.py            # rewrites docs/python-api.md
    tools/python_api_reference.py --check    # exit 1 if docs/python-api.md is not what it would write

Reads python/vktg/*.py with ast (nothing is imported, so neither the native module nor torch is
needed): every name in a module's __all__, its signature and docstring; a class's public methods
and properties.
"""

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODULES = [("vktg", ROOT / "python" / "vktg" / "__init__.py"), ("vktg.torch", ROOT / "python" / "vktg" / "torch.py")]
OUT = ROOT / "docs" / "python-api.md"


def signature(node: ast.FunctionDef, drop_self: bool) -> str:
    args = ast.unparse(node.args)
    if drop_self and args.startswith("self"):
        args = args[len("self"):].lstrip(", ")
    returns = f" -> {ast.unparse(node.returns)}" if node.returns else ""
    return f"({args}){returns}"


def exported(tree: ast.Module) -> list:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return [ast.literal_eval(e) for e in node.value.elts]
    return []


def doc(node) -> str:
    text = ast.get_docstring(node)
    return text.strip() + "\n" if text else ""


def reference() -> str:
    lines = ["# Python API reference", "",
             "Generated from the docstrings by `tools/python_api_reference.py` (a test checks it is current);",
             "docs/python.md is the guide.", ""]
    for module, path in MODULES:
        tree = ast.parse(path.read_text())
        lines += [f"## `{module}`", "", doc(tree)]
        nodes = {n.name: n for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        for name in exported(tree):
            node = nodes.get(name)
            if node is None:  # re-exported from the native module
                lines += [f"### `{module}.{name}`", "", "The exception every error of vktg raises (a subclass of "
                          "Exception), with the command line's message.", ""]
                continue
            if isinstance(node, ast.FunctionDef):
                lines += [f"### `{module}.{name}{signature(node, False)}`", "", doc(node)]
                continue
            init = next((n for n in node.body if isinstance(n, ast.FunctionDef) and n.name == "__init__"), None)
            lines += [f"### class `{module}.{name}{signature(init, True) if init else ''}`", "", doc(node)]
            fields = [n for n in node.body if isinstance(n, ast.AnnAssign)]
            if fields:
                lines.append("Fields: " + ", ".join(f"`{ast.unparse(f.target)}`" for f in fields) + ".\n")
            for member in node.body:
                if not isinstance(member, ast.FunctionDef) or member.name.startswith("_"):
                    continue
                decorators = {ast.unparse(d) for d in member.decorator_list}
                if "property" in decorators:
                    lines += [f"- `{name}.{member.name}` (property)" + (f": {doc(member).strip()}" if doc(member) else "")]
                else:
                    static = "staticmethod" in decorators
                    lines += [f"- `{name}.{member.name}{signature(member, not static)}`" +
                              (f": {doc(member).strip()}" if doc(member) else "")]
            lines.append("")
    return "\n".join(lines).rstrip("\n") + "\n"


if __name__ == "__main__":
    text = reference()
    if "--check" in sys.argv:
        if not OUT.exists() or OUT.read_text() != text:
            print(f"{OUT} is not current: run tools/python_api_reference.py", file=sys.stderr)
            sys.exit(1)
        sys.exit(0)
    OUT.write_text(text)
    print(f"wrote {OUT}")
