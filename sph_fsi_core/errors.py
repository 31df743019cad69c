"""The error a user's input gets, at the ground floor so that every module can raise it: a bad scene key or value,
a scene that cannot be built, a setting a solver refuses (a forced step above its stable limit). The simulation's
own failure, a run that diverged, is diagnostics.Diverged."""


class SceneError(ValueError):
    """Bad scene input: the message names the key, the bad value and what is allowed."""
