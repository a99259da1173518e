"""CATCH and THROW, and the F83 aborts built on them.

Every Forth error is a ForthError carrying a THROW code; CATCH catches it,
puts the stacks back to their depths at CATCH and pushes the code.
"""
from rcl.errors import ForthError
from rcl.forth.memory import MASK, signed
from rcl.forth import state
from rcl.forth.primitives import CALL, prim

# The message of the last ABORT" CATCH caught, for THROW -2: the session's.
state.session("abort_message", lambda m: "")


@prim("CATCH", "( i*x xt -- j*x 0 | i*x n ) run xt; catch what it throws", kind=CALL)
def catch(m):
    xt = m.s.pop()
    depth, rdepth, nsrc = len(m.s), len(m.rs), len(m.sources)
    try:
        m.execute(xt)
    except (ForthError, IndexError, RecursionError) as exc:
        e = m.forth_error(exc)
        del m.rs[rdepth:]
        del m.s[depth:]
        m.s.extend([0] * (depth - len(m.s)))
        while len(m.sources) > nsrc:
            m.pop_source()
        m.s.append(e.code & MASK)
        if e.code == -2:
            m.abort_message = e.message
    else:
        m.s.append(0)


@prim("THROW", "( k*x n -- k*x | i*x n ) throw n unless it is 0")
def throw(m):
    n = signed(m.s.pop())
    if n == -2:
        raise ForthError(-2, m.abort_message)
    if n:
        raise ForthError(n)


@prim("ABORT", "( -- ) empty the stacks and go back to the prompt")
def abort(m):
    raise ForthError(-1)


@prim("QUIT", "( -- ) empty the return stack and go back to the prompt")
def quit_(m):
    raise ForthError(-56, "")
