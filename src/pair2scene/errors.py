"""Errors a user can cause. The CLI prints their message as one line and exits with 2."""

from __future__ import annotations

import math
from collections.abc import Mapping


class UserError(Exception):
    """Bad input: a malformed file, an unknown source, an impossible request."""

    exit_code = 2


class SceneFileError(UserError):
    """A scene.json that does not follow the contract: names the file and the field."""

    def __init__(self, path: str, field: str, problem: str) -> None:
        self.path, self.field, self.problem = path, field, problem
        super().__init__(f"{path}: {field}: {problem}")


def check_ranges(
    prefix: str,
    positive: Mapping[str, float] = {},  # noqa: B006  (read only)
    non_negative: Mapping[str, float] = {},  # noqa: B006
) -> None:
    """Raise a :class:`UserError` naming the option (``prefix`` + the field's name with
    dashes, as the CLI spells it) of the first value that is not finite and > 0
    (``positive``) or >= 0 (``non_negative``)."""
    for bound, values in ((">", positive), (">=", non_negative)):
        for name, value in values.items():
            ok = math.isfinite(value) and (value > 0 if bound == ">" else value >= 0)
            if not ok:
                flag = prefix + name.replace("_", "-")
                raise UserError(f"{flag} must be {bound} 0, got {value}")
