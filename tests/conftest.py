from __future__ import annotations

from pathlib import Path

import pytest

FIXTURES = Path(__file__).parent / "fixtures"
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
PROCTHOR_1K = SHARED / "data" / "procthor-1k"


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
    if not PROCTHOR_1K.is_dir():
        pytest.fail(f"{PROCTHOR_1K} is missing: tests expect ../shared beside the checkout")
    return PROCTHOR_1K
