"""The error a user's input gets, at the ground floor so that every module can raise it: a bad scene key or value,
a scene that cannot be built, a setting a solver refuses (a forced step above its stable limit). The simulation's
own failure, a run that diverged, is diagnostics.Diverged."""


class SceneError(ValueError):
    """Bad scene input: the message names the key, the bad value and what is allowed."""


def plain(value, digits=6):
    """A number or a sequence of numbers as a message shows it, `0.1` or `[0, 0.05, 0.1]`: plain numbers to
    `digits` significant digits, never NumPy's reprs (`np.float64(0.1)`, `[0.   0.05 0.1 ]`)."""
    if hasattr(value, "__len__") and not isinstance(value, str):
        return "[" + ", ".join(plain(v, digits) for v in value) + "]"
    return f"{float(value):.{digits}g}"
