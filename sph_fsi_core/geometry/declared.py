"""A geometry scene's own named parameters and derived quantities, declared under `geometry:` in its file.

    geometry:
      length: {value: 0.04, unit: m, range: "(0, 10]", description: "Beam length L (x), clamp face to free end"}
      clamp_layers: {value: 4, unit: "1", range: [1, 20], description: "Layers of the clamp behind the root"}
      periodic_y: {value: true, unit: "", description: "Periodic along y (else side walls close the slab)"}
      release: {value: lifted, unit: "", choices: [instant, lifted], description: "How the gate goes"}
      wall_top: {expression: "ceil(wall_height / dp - 1e-9) * dp", unit: m, description: "The walls' top"}

A parameter (`value`) is a scene key like any other, `geometry.<name>`: checked by type and range, set by `--set
geometry.length=0.06`, a ROS parameter of the node, listed by `sph-fsi keys`. Its type is its value's: true/false,
an integer, a number or a string (with `choices`, one of them). `range` is [low, high] (both included) or an interval
as text, "(0, 10]" (a round bracket leaves its end out; null or inf: unbounded).

A derived quantity (`expression`) is not a key: it follows from the parameters, the scene's keys and the derived
quantities declared before it (geometry/expressions.py), so a value used in several places is written once. The
resolved values hold it as `geometry.<name>` beside the keys, for the scene's case module.

The parts', probes' and judges' numbers (and the geometry builder's own keys) may be expressions in both, so a case
stays one file that a user reads and varies: `--set geometry.length=0.06` moves the beam's free end and its probe.
"""
import math
import re

from ..schema import Param, SceneError
from .expressions import CONSTANTS, FUNCTIONS

FIELDS = ("value", "expression", "unit", "range", "description", "choices")
SET = " set"    # where an override's value waits beside the declaration (a field no file can write by accident)
NAME_RE = re.compile(r"[a-z][a-z0-9_]*\Z")
SECTIONS = ("scene", "numerics", "solid", "fluid", "coupling", "output", "watchdog", "geometry", "parts", "probes",
            "judge")


def is_declaration(value):
    """Whether a `geometry:` entry is a declaration (a mapping) rather than a builder key's value."""
    return isinstance(value, dict)


def _interval(key, text):
    """(low, high, low included, high included) of an interval written "(0, 10]"."""
    match = re.fullmatch(r"\s*([\[(])\s*([^,]*?)\s*,\s*([^,]*?)\s*([\])])\s*", text)
    if not match:
        raise SceneError(f"{key}.range = {text!r}: not an interval; allowed: [low, high] or text such as \"(0, 10]\"")
    ends = []
    for raw in (match.group(2), match.group(3)):
        if raw.lower() in ("", "null", "none", "inf", "+inf", "-inf"):
            ends.append(None)
            continue
        try:
            ends.append(float(raw))
        except ValueError:
            raise SceneError(f"{key}.range = {text!r}: {raw!r} is not a number; allowed: numbers, or inf") from None
    return ends[0], ends[1], match.group(1) == "[", match.group(4) == "]"


def _range(key, raw, kind):
    if raw is None:
        return None, None, True, True
    if kind not in ("int", "float"):
        raise SceneError(f"{key}.range: a {kind} parameter has no range; allowed: a range for a number only")
    if isinstance(raw, str):
        low, high, low_in, high_in = _interval(key, raw)
    elif isinstance(raw, list) and len(raw) == 2 and all(v is None or (isinstance(v, (int, float))
                                                                         and not isinstance(v, bool)) for v in raw):
        low, high = (None if v is None or math.isinf(v) else float(v) for v in raw)
        low_in = high_in = True
    else:
        raise SceneError(f"{key}.range = {raw!r}: not a range; allowed: [low, high] (both included) or text such as "
                         f"\"(0, 10]\"")
    if low is not None and high is not None and low > high:
        raise SceneError(f"{key}.range = {raw!r}: low above high; allowed: low <= high")
    return low, high, low_in, high_in


def _kind(key, value):
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, float):
        return "float"
    if isinstance(value, str):
        return "str"
    raise SceneError(f"{key}.value = {value!r}: not a parameter's value; allowed: a number, true or false, or a "
                     f"string")


def check_name(key, reserved):
    """SceneError unless `key`'s name may name a parameter: lower case, not a constant, a function, a section or
    one of the builder's own keys (`reserved`)."""
    name = key.split(".", 1)[1]
    if not NAME_RE.match(name):
        raise SceneError(f"{key}: not a parameter's name; allowed: lower-case letters, digits and '_', starting with a "
                         f"letter")
    if name in CONSTANTS or name in FUNCTIONS or name in SECTIONS or name in ("true", "false") or name in reserved:
        raise SceneError(f"{key}: {name!r} is taken (a constant, function, section or the builder's own key); "
                         f"allowed: another name")


def parameter(key, body, reserved):
    """The schema.Param of a declaration with a `value` (SceneError naming what is wrong with it)."""
    check_name(key, reserved)
    unknown = [f for f in body if f not in FIELDS and f != SET]
    if unknown:
        raise SceneError(f"{key}.{unknown[0]}: not a field of a declared parameter; allowed: "
                         + ", ".join(f for f in FIELDS if f != "expression"))
    if "unit" not in body or not isinstance(body["unit"], str):
        raise SceneError(f"{key}.unit: missing; allowed: its unit as text ('m', 'Pa', '1' for a count or ratio, '' "
                         f"for a choice or a switch)")
    value = body["value"]
    kind = _kind(key, value)
    low, high, low_in, high_in = _range(key, body.get("range"), kind)
    choices = body.get("choices", ())
    if choices and (kind != "str" or not isinstance(choices, list) or not all(isinstance(c, str) for c in choices)):
        raise SceneError(f"{key}.choices = {choices!r}: allowed: a list of strings, for a string parameter")
    description = body.get("description", "")
    if not isinstance(description, str):
        raise SceneError(f"{key}.description: expected text")
    param = Param(key, value, body["unit"], description or "The scene's own parameter", kind=kind, low=low,
                  high=high, low_inclusive=low_in, high_inclusive=high_in, choices=tuple(choices))
    param.coerce(value)
    return param


def derived(key, body, reserved):
    """(expression text, unit, description) of a declaration with an `expression`."""
    check_name(key, reserved)
    unknown = [f for f in body if f not in ("expression", "unit", "description")]
    if unknown:
        raise SceneError(f"{key}.{unknown[0]}: not a field of a derived quantity; allowed: expression, unit, "
                         f"description")
    text = body["expression"]
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise SceneError(f"{key}.expression = {text!r}: allowed: an expression (text) or a number")
    return str(text), body.get("unit", ""), body.get("description", "")


def declarations(flat, reserved):
    """(the Params of the scene's declared parameters, {key: (expression, unit, description)} of its derived
    quantities in file order) from the flat keys, where a declaration is a mapping under `geometry.` (an override
    of a parameter arrives merged into it: `overlaid`)."""
    params, derived_ = [], {}
    for key, body in flat.items():
        if not key.startswith("geometry.") or not is_declaration(body):
            continue
        if ("value" in body) == ("expression" in body):
            raise SceneError(f"{key}: a declaration has a value (a parameter) or an expression (a derived quantity), "
                             f"not {'both' if 'value' in body else 'neither'}")
        if "value" in body:
            params.append(parameter(key, body, reserved))
        else:
            derived_[key] = derived(key, body, reserved)
    return params, derived_


def overlaid(flat, overrides):
    """The flat keys with `overrides` applied; a declared parameter keeps its declaration (its type, range) and
    takes the value beside it (value_of).
    SceneError for an override of a derived quantity (it follows from the parameters)."""
    out = dict(flat)
    for key, value in overrides.items():
        body = out.get(key)
        if is_declaration(body) and "expression" in body and not is_declaration(value):
            raise SceneError(f"{key} = {value!r}: a quantity the scene derives ({body['expression']}), not a key; "
                             f"allowed: set the parameters it follows from")
        out[key] = {**body, SET: value} if is_declaration(body) and not is_declaration(value) else value
    return out


def value_of(body):
    """A declared parameter's value: the one set over the file's (overlaid), else the file's."""
    return body[SET] if SET in body else body["value"]
