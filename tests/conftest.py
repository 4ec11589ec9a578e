from __future__ import annotations

from pathlib import Path

import pytest

FIXTURES = Path(__file__).parent / "fixtures"
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
PROCTHOR_1K = SHARED / "data" / "procthor-1k"
NO_SHARED = f"needs the full ProcTHOR-1k data at {PROCTHOR_1K} (../shared beside the checkout)"


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    # A test that takes the procthor_1k fixture needs the full data set, marked or not.
    for item in items:
        if "procthor_1k" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.shared_data)


def pytest_runtest_setup(item: pytest.Item) -> None:
    # Tests marked shared_data need the full data set; CI has it beside the clone,
    # a fresh machine does not. Skip (not deselect) so they still run where it exists.
    if item.get_closest_marker("shared_data") and not PROCTHOR_1K.is_dir():
        pytest.skip(NO_SHARED)


@pytest.fixture(scope="session")
def fixtures() -> Path:
    return FIXTURES


@pytest.fixture(scope="session")
def ai2thor_databases() -> Path:
    """The full AI2-THOR databases, fetched from PyPI into the cache once."""
    from pair2scene.data.fetch import databases_dir

    return databases_dir()


@pytest.fixture(scope="session")
def ai2thor_corpus(ai2thor_databases):
    from pair2scene.data.ai2thor import load_ai2thor

    return load_ai2thor(ai2thor_databases)


@pytest.fixture(scope="session")
def procthor_1k() -> Path:
    """The full ProcTHOR-1k folder; tests using it are marked shared_data (and skipped
    without it). Tests that only need some houses use fixtures / "procthor" instead."""
    return PROCTHOR_1K
