"""Test configuration: Hypothesis profiles and the shared helper module.

The "ci" profile (the default) is deterministic: Hypothesis derives its examples
from each test's source, so every run of the suite draws the same states.  Select
another profile with ``HYPOTHESIS_PROFILE=dev`` (more, random examples).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci",
    derandomize=True,
    max_examples=30,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("dev", max_examples=300, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

# Make `import lagrangian_test_support` work from any test module (--import-mode=importlib
# does not put test directories on sys.path).
_HERE = str(Path(__file__).resolve().parent)
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)
