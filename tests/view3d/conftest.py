"""One headless Chromium per test module of the 3-D view (skipped, with the reason, where there is none)."""

from __future__ import annotations

import pytest

from lagrangian.view3d._chromium import Browser, find_chromium


@pytest.fixture(scope="module")
def browser():
    if find_chromium() is None:
        pytest.skip("no headless Chromium on this machine (`make test` installs Debian's chromium as root)")
    with Browser() as b:
        yield b
