"""`python3 -m rcl`: the same as the `rcl` command."""
import sys

from rcl.cli import main   # (Ctrl-C while it loads: a quiet exit, see cli.py)

sys.exit(main())
