"""Primitive word sets, one module per set. Importing this package registers
them all, in this order (the order fixes each primitive's number)."""
from rcl.forth import inner  # noqa: F401  (runtimes and control words first)
from rcl.words import core, memory_access, double, compiling, io, parsing, tools, vocab  # noqa: F401
from rcl.words import exceptions, blocks, files, system, ports, rclcode  # noqa: F401
from rcl.words import tracing, saving  # noqa: F401
from rcl.words import fileaccess, heap, strings, toolsext  # noqa: F401  (new sets last:
from rcl.words import facility, localvars  # noqa: F401   earlier numbers stay)
from rcl.words import tester  # noqa: F401  (T{ -> }T)
from rcl.words import help  # noqa: F401
from rcl.words import faults  # noqa: F401  (the simulated board's faults, from Forth)
from rcl.words import moves  # noqa: F401  (the move log, .MOVES)
from rcl.words import debugging  # noqa: F401  (DBG, BREAK:, ~~)
