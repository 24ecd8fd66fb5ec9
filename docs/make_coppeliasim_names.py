"""Regenerate ``puckboard/backends/coppeliasim/server/api/coppeliasim_sim.json``: the names of CoppeliaSim's ``sim`` API.

``puckboard serve`` lists CoppeliaSim's whole ``sim`` namespace to a client (the official
client only creates ``sim.<name>`` for names the server lists), so a call to a function
the server does not serve reaches the server and gets a clear answer instead of a bare
``AttributeError`` in the client. This script extracts those names, and the constants'
values, from CoppeliaSim's public sources at one release tag:

* functions and constants registered in C++: ``sourceCode/interfaces/luaScriptFunctions.cpp``
  of CoppeliaRobotics/coppeliaSimLib;
* functions written in Lua: ``sim.lua``, ``sim-deprecated.lua``, ``sim-ce.lua`` of
  CoppeliaRobotics/lua;
* constants' values: the enums of ``simLib/simConst.h`` of CoppeliaRobotics/include.

Only names and numbers are taken (the interface, not the implementation). Usage, with the
three repositories cloned side by side::

    python docs/make_coppeliasim_names.py --tag coppeliasim-v4.7.0-rev2 \\
        --simlib ../coppeliaSimLib --lua ../lua --include ../include
"""

from __future__ import annotations

import argparse
import ast
import contextlib
import json
import operator
import re
import subprocess
from pathlib import Path

OUT = (
    Path(__file__).resolve().parents[1]
    / "puckboard"
    / "backends"
    / "coppeliasim"
    / "server"
    / "api"
    / "coppeliasim_sim.json"
)

_REGISTERED = re.compile(r'\{"sim\.([A-Za-z0-9_]+)",\s*([^}]+?)\s*\}')
_LUA_FUNCTION = re.compile(
    r"^\s*function sim\.([A-Za-z0-9_]+)\s*\(|^\s*sim\.([A-Za-z0-9_]+)\s*=\s*function", re.M
)
_ENUM = re.compile(r"enum\s*\{(.*?)\}\s*;", re.S)
_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_BINARY = {
    ast.BitOr: operator.or_, ast.BitAnd: operator.and_, ast.LShift: operator.lshift,
    ast.RShift: operator.rshift, ast.Add: operator.add, ast.Sub: operator.sub,
    ast.Mult: operator.mul,
}  # fmt: skip


def _show(repo: Path, tag: str, path: str) -> str:
    return subprocess.run(
        ["git", "-C", str(repo), "show", f"{tag}:{path}"], check=True, capture_output=True,
        text=True,
    ).stdout  # fmt: skip


def _value(expr: str, known: dict[str, int]) -> int:
    """An enum initialiser's value: integers, names already known, | & << >> + - * ( )."""

    def walk(node: ast.AST) -> int:
        if isinstance(node, ast.Constant) and isinstance(node.value, int):
            return node.value
        if isinstance(node, ast.Name):
            return known[node.id]
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
            return -walk(node.operand)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Invert):
            return ~walk(node.operand)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](walk(node.left), walk(node.right))
        raise ValueError(f"cannot evaluate {expr!r}")

    return walk(ast.parse(expr.strip(), mode="eval").body)


def enum_values(header: str) -> dict[str, int]:
    known: dict[str, int] = {}
    for body in _ENUM.findall(_COMMENT.sub("", header)):
        nxt = 0
        for item in (i.strip() for i in body.split(",")):
            if not item:
                continue
            name, _, expr = (p.strip() for p in item.partition("="))
            try:
                value = _value(expr, known) if expr else nxt
            except (KeyError, ValueError, SyntaxError):
                continue
            known[name] = value
            nxt = value + 1
    return known


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tag", default="coppeliasim-v4.7.0-rev2")
    parser.add_argument("--simlib", type=Path, required=True)
    parser.add_argument("--lua", type=Path, required=True)
    parser.add_argument("--include", type=Path, required=True)
    args = parser.parse_args()
    registered = _show(args.simlib, args.tag, "sourceCode/interfaces/luaScriptFunctions.cpp")
    values = enum_values(_show(args.include, args.tag, "simLib/simConst.h"))
    functions: set[str] = set()
    constants: dict[str, int] = {}
    for name, target in _REGISTERED.findall(registered):
        if target.startswith("_sim"):
            functions.add(name)
        elif target in values:
            constants[name] = values[target]
        else:  # an expression of macros some constants use: not needed by any e-puck client
            with contextlib.suppress(KeyError, ValueError, SyntaxError):
                constants[name] = _value(target, values)
    for path in ("sim.lua", "sim-deprecated.lua", "sim-ce.lua"):
        for a, b in _LUA_FUNCTION.findall(_show(args.lua, args.tag, path)):
            functions.add(a or b)
    data = {
        "source": (
            f"CoppeliaSim {args.tag}: coppeliaSimLib sourceCode/interfaces/luaScriptFunctions.cpp, "
            "lua sim.lua / sim-deprecated.lua / sim-ce.lua, include simLib/simConst.h"
        ),
        "functions": sorted(functions),
        "constants": dict(sorted(constants.items())),
    }
    OUT.write_text(json.dumps(data, indent=0) + "\n", encoding="utf-8")
    print(f"{OUT}: {len(functions)} functions, {len(constants)} constants")


if __name__ == "__main__":
    main()
