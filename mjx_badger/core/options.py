"""Field types the command line reads from the config dataclasses (tyro builds the options from them).

A `Pairs` field is a tuple of (name, value) pairs, given on the command line as repeated
NAME=VALUE options, the value read as a Python literal (a bare word stays a string).
"""

import ast
from typing import Annotated

import tyro
from tyro.constructors import PrimitiveConstructorSpec


def name_value(text: str) -> tuple:
    """NAME=VALUE as (name, value); a list value becomes a tuple so the pair stays hashable."""
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise ValueError(f"expected NAME=VALUE, got {text!r}")
    try:
        parsed = ast.literal_eval(value)
    except (ValueError, SyntaxError):
        parsed = value  # a bare word such as thesis-text or butterworth
    return name, tuple(parsed) if isinstance(parsed, list) else parsed


Pair = Annotated[tuple, PrimitiveConstructorSpec(
    nargs=1, metavar="NAME=VALUE", instance_from_str=lambda args: name_value(args[0]),
    is_instance=lambda x: isinstance(x, tuple) and len(x) == 2, str_from_instance=lambda pair: ["{}={}".format(*pair)])]


def pairs(alias: str):
    """A tuple of NAME=VALUE pairs, one per repeated `alias` option (or the field's own name)."""
    return Annotated[tuple[Pair, ...], tyro.conf.UseAppendAction, tyro.conf.arg(aliases=(alias,))]
