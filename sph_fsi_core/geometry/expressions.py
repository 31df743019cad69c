"""Arithmetic in a scene file: a number of a part, probe, judge or geometry key written as an expression in the
scene's own parameters (geometry/declared.py), evaluated safely from Python's syntax tree (no `eval`).

    size: [length + clamp_layers * dp, width, thickness]
    lift_travel: round(column_height / dp) * dp + 2 * h
    period: [0, "span if periodic_y else 0", 0]

Allowed: numbers, strings and true/false; + - * / // % ** and parentheses; comparisons, `and`, `or`, `not` and
`a if condition else b`; the functions in FUNCTIONS; the names in the namespace: the scene's declared parameters and
derived quantities by name, `dp` (numerics.spacing), `h` (numerics.smoothing_ratio * dp), `pi`, and any key the
scene has by its dotted name (`numerics.spacing`, `solid.clamp`, `fluid.density`, `scene.gravity[2]`). Python's own
arithmetic is used, operation by operation, so an expression gives the bits the same formula gives in code.

A vector key (`[x, y, z]`) has an expression per component. YAML ends a plain value in a flow list at a comma: a
component with a comma of its own (`max(a, b)`) is quoted.
"""
import ast
import difflib
import math
import operator

from ..errors import SceneError

FUNCTIONS = {"min": min, "max": max, "round": round, "ceil": math.ceil, "floor": math.floor, "abs": abs,
             "sqrt": math.sqrt, "tanh": math.tanh}
# names an expression always has besides the scene's (the scene's own may not take them)
CONSTANTS = ("dp", "h", "pi")
MAX_LENGTH = 1000
MAX_EXPONENT = 1000

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_COMPARE = {ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le,
            ast.Gt: operator.gt, ast.GtE: operator.ge}
ALLOWED = ("numbers, strings, true/false, + - * / // % ** ( ), comparisons, and/or/not, 'a if c else b', "
           + ", ".join(FUNCTIONS) + ", and the names " + ", ".join(CONSTANTS) + ", the scene's parameters and its "
           "keys by dotted name")


class ExpressionError(ValueError):
    """What is wrong with an expression (the caller names the key)."""


class Namespace:
    """What an expression's names mean: `names` {name: value} (the scene's parameters, derived quantities and the
    constants) and `keys` {dotted key: value} (every key the scene has)."""

    def __init__(self, names, keys):
        self.names = dict(names)
        self.keys = keys

    def name(self, name):
        if name in self.names:
            return self.names[name]
        near = difflib.get_close_matches(name, list(self.names) + list(FUNCTIONS), n=1, cutoff=0.6)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        raise ExpressionError(f"unknown name {name!r}{hint}; the scene's names: " + ", ".join(sorted(self.names)))

    def key(self, section, name):
        key = f"{section}.{name}"
        if key in self.keys:
            return self.keys[key]
        near = difflib.get_close_matches(key, [k for k in self.keys if k.startswith(section + ".")], n=1,
                                         cutoff=0.6)
        hint = f" (did you mean {near[0]!r}?)" if near else ""
        raise ExpressionError(f"unknown key {key!r}{hint}")


def namespace(values, names):
    """The Namespace of a scene's resolved `values` with its own `names` (parameters and derived quantities) and the
    constants dp, h and pi where the scene has a spacing."""
    out = dict(names)
    if "numerics.spacing" in values:
        dp = values["numerics.spacing"]
        out.update(dp=dp, h=values["numerics.smoothing_ratio"] * dp)
    out["pi"] = math.pi
    return Namespace(out, values)


def parse(text):
    """The syntax tree of an expression (ExpressionError if it is not one of the allowed kind)."""
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"longer than {MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        raise ExpressionError(f"not an expression ({exc.msg})") from None
    return tree.body


def evaluate(text, space):
    """The value of expression `text` in Namespace `space`: a number, a bool or a string."""
    return _value(parse(text), space)


def _number(x, node):
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise ExpressionError(f"{ast.unparse(node)!r} is {x!r}, not a number")
    return x


def _value(node, space):
    if isinstance(node, ast.Constant):
        if isinstance(node.value, (bool, int, float, str)):
            return node.value
        raise ExpressionError(f"{node.value!r} is not a number, a string or true/false")
    if isinstance(node, ast.Name):
        if node.id in ("true", "false"):
            return node.id == "true"
        return space.name(node.id)
    if isinstance(node, ast.Attribute):
        if not isinstance(node.value, ast.Name):
            raise ExpressionError(f"{ast.unparse(node)!r}: only a section's key, as section.key")
        return space.key(node.value.id, node.attr)
    if isinstance(node, ast.Subscript):
        seq = _value(node.value, space)
        index = _value(node.slice, space)
        if not isinstance(seq, tuple) or isinstance(index, bool) or not isinstance(index, int) \
                or not -len(seq) <= index < len(seq):
            raise ExpressionError(f"{ast.unparse(node)!r}: only a vector's component, [0], [1] or [2]")
        return seq[index]
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left = _number(_value(node.left, space), node.left)
        right = _number(_value(node.right, space), node.right)
        if isinstance(node.op, ast.Pow) and abs(right) > MAX_EXPONENT:
            raise ExpressionError(f"{ast.unparse(node)!r}: an exponent beyond {MAX_EXPONENT}")
        try:
            return _BINARY[type(node.op)](left, right)
        except (ZeroDivisionError, OverflowError) as exc:
            raise ExpressionError(f"{ast.unparse(node)!r}: {exc}") from None
    if isinstance(node, ast.UnaryOp):
        operand = _value(node.operand, space)
        if isinstance(node.op, ast.Not):
            return not operand
        if isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = _number(operand, node.operand)
            return -operand if isinstance(node.op, ast.USub) else +operand
    if isinstance(node, ast.BoolOp):
        result = None
        for item in node.values:
            result = _value(item, space)
            if isinstance(node.op, ast.And) and not result or isinstance(node.op, ast.Or) and result:
                return result
        return result
    if isinstance(node, ast.Compare):
        left = _value(node.left, space)
        for op, right_node in zip(node.ops, node.comparators):
            if type(op) not in _COMPARE:
                break
            right = _value(right_node, space)
            try:
                if not _COMPARE[type(op)](left, right):
                    return False
            except TypeError:
                raise ExpressionError(f"{ast.unparse(node)!r}: compares {left!r} with {right!r}") from None
            left = right
        else:
            return True
    if isinstance(node, ast.IfExp):
        return _value(node.body if _value(node.test, space) else node.orelse, space)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS \
            and not node.keywords:
        args = [_number(_value(a, space), a) for a in node.args]
        try:
            return FUNCTIONS[node.func.id](*args)
        except (TypeError, ValueError, OverflowError) as exc:
            raise ExpressionError(f"{ast.unparse(node)!r}: {exc}") from None
    raise ExpressionError(f"{ast.unparse(node)!r} is not allowed; allowed: {ALLOWED}")


def refusal(key, text, exc):
    """The SceneError for key = text whose expression failed with `exc`."""
    return SceneError(f"{key} = {text!r}: {exc}; allowed: an expression of {ALLOWED}")
