"""Web view tests need aiohttp; browser tests also need a Chromium binary."""

from __future__ import annotations

import pytest

pytest.importorskip("aiohttp")
