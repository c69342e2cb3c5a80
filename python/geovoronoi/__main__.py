"""``python -m geovoronoi``: the geovoronoi command-line tool (docs/cli.md), the same C++ code.

Every command, option, output file, message and exit code is the tool's: 0 success, 2 usage or bad
input, 1 runtime failure; ``python -m geovoronoi --help`` lists the commands.
"""

from __future__ import annotations

import signal
import sys
from typing import Optional, Sequence

from geovoronoi import _geovoronoi


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Runs the command line ``argv`` (default: this process's arguments) and returns its exit code."""
    args = list(sys.argv[1:] if argv is None else argv)
    # the tool writes through C's stdio: what Python buffered goes first
    sys.stdout.flush()
    sys.stderr.flush()
    return _geovoronoi.cli_main(args)


if __name__ == "__main__":
    # The process is the tool's: Ctrl-C, SIGTERM and SIGHUP end the run as they end the tool (its
    # output folder removes its partial files first), a closed pipe ends it as it ends the tool.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    sys.exit(main())
