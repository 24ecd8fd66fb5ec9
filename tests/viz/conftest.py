import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("matplotlib")
import matplotlib

matplotlib.use("Agg")  # no test ever opens a window
