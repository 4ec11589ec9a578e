"""Errors a user can cause. The CLI prints their message as one line and exits with 2."""

from __future__ import annotations


class UserError(Exception):
    """Bad input: a malformed file, an unknown source, an impossible request."""

    exit_code = 2


class SceneFileError(UserError):
    """A scene.json that does not follow the contract: names the file and the field."""

    def __init__(self, path: str, field: str, problem: str) -> None:
        self.path, self.field, self.problem = path, field, problem
        super().__init__(f"{path}: {field}: {problem}")
