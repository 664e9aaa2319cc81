"""What a command-line process imports before it plans: heavy libraries only where used.

Every verb's parser is built at start-up (``build_parser``), so a module a verb imports at
its top is paid by every command. meshcat (with IPython, tornado and zmq, ~0.07 s) is for
``replay`` only and scipy.spatial (~0.05 s) for roadmaps past a few hundred poses: neither
may be imported by building the parser or by importing the API.
"""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("meshcat", "IPython", "tornado", "zmq", "scipy.spatial")

PROBE = """
import json, sys
from pivot_ompl.cli.main import build_parser
import pivot_ompl.api
parser = build_parser()
parser.parse_args(["plan", "door", "--time", "1"])
print(json.dumps(sorted(sys.modules)))
"""


def test_parser_and_api_import_no_viewer_nor_kd_tree() -> None:
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                         check=True, timeout=120)
    loaded = set(json.loads(out.stdout.strip().splitlines()[-1]))
    assert "pivot_ompl.cli.replay" in loaded  # every verb registered
    heavy = sorted(m for m in loaded if any(m == h or m.startswith(h + ".") for h in HEAVY))
    assert heavy == []
