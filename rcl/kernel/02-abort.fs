\ Kernel: ON-ABORT runs after every error, Ctrl-C and ABORT, once the
\ stacks are empty and the board's motors are off (a layer above can make
\ its own state safe too, as RCL does with its relay shadow).
DEFER ON-ABORT  ( -- )
' NOOP IS ON-ABORT
