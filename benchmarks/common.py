"""What the benchmark scripts share: writing their figures as JSON."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any


def _finite(x: Any) -> Any:
    """``x`` with NaN and infinities as ``None`` (JSON has neither)."""
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, dict):
        return {k: _finite(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_finite(v) for v in x]
    return x


def write_json(res: dict[str, Any], out: str | Path) -> Path:
    """Write ``res`` to ``out`` (folders made as needed) and say so."""
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(_finite(res), indent=1, default=float, allow_nan=False) + "\n")
    print(f"written {path}")
    return path
