"""``python -m pivot_ompl.analysis.prover_main FD``: a prover's process.

:class:`~pivot_ompl.analysis.prover.Prover` starts it with one end of a socket pair as ``FD``
and sends its job through it (:func:`~pivot_ompl.analysis.prover.serve`).
"""

from __future__ import annotations

import signal
import sys
from multiprocessing.connection import Connection

from pivot_ompl.analysis.prover import serve


def main(argv: list[str]) -> int:
    """Serve the job sent through the socket whose descriptor is ``argv[1]``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the plan's: it closes the socket
    conn = Connection(int(argv[1]))
    try:
        serve(conn)
    finally:
        conn.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
