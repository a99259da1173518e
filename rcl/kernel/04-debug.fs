\ Kernel: BREAKS, the switch of every BREAK: and BREAK" compiled (on at
\ start): BREAKS OFF runs through them all without recompiling.
VARIABLE BREAKS  ( -- addr )   \ on: BREAK: stops; BREAKS OFF runs through
BREAKS ON
