\ Kernel: what runs after every error, Ctrl-C and ABORT, once the stacks
\ are empty and the board's motors are off: first the system's own
\ safe-state word (its xt in SAFE-STATE, 0 for none: RCL clears its relay
\ shadow and move state there), then ON-ABORT, the user's hook. Then the
\ machine stops the motors again, whatever the hook did.
VARIABLE SAFE-STATE  ( -- addr )
DEFER ON-ABORT  ( -- )
' NOOP IS ON-ABORT
