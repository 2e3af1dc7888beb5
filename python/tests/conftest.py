"""Shared fixtures: the Rust crate's answers for the bit-identity tests."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def golden():
    """The `golden` example's output, one case per line, keyed by case:
    run with cargo here, so the answers always come from the Rust crate
    built from this tree."""
    out = subprocess.run(
        ["cargo", "run", "--release", "--quiet", "-p", "hrla-python", "--example", "golden"],
        cwd=ROOT, check=True, capture_output=True, text=True, env=os.environ,
    ).stdout
    cases = [json.loads(line) for line in out.splitlines() if line.strip()]
    assert len(cases) == 5, out
    return {c["case"]: c for c in cases}
