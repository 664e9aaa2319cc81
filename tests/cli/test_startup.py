"""What a command's start-up imports: only what its verb needs.

Every verb's parser is built at start-up (its module imported); a module whose heavy
optional dependency only one verb uses imports it when that verb runs.
"""

from __future__ import annotations

import subprocess
import sys


def test_building_the_parser_does_not_import_the_viewer():
    # regression: the replay verb imported meshcat (and its tornado/zmq server) at start-up,
    # 0.15 s of every plan's whole process
    code = ("import sys\nfrom pivot_ompl.cli.main import main\nmain(['--help'])\n"
            "print('meshcat' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert "replay" in out  # the verb is offered
    assert out.split()[-1] == "False"
