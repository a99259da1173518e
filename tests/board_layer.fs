\ A minimal hardware layer of our own, to drive the simulated board without
\ RCL (RCL's real one is screens/10-hardware.fs and on): 8253 set-up, a
\ speed count, reading the encoder counters, the vector table, timer 0,
\ the BIOS time of day.
\ Used by tests/test_board.py and bench/board.py.
HEX
: INIT-8253 ( base -- )  >R  36 R@ 3 + PC!  0 R@ PC!  0 R@ PC!
   74 R@ 3 + PC!  0 R@ 1+ PC!  0 R@ 1+ PC!  B4 R@ 3 + PC!  0 R@ 2+ PC!  0 R@ 2+ PC!
   R> DROP ;
: REF! ( n base -- )  >R  DUP FF AND R@ PC!  8 RSHIFT R> PC! ;
: CNT ( port -- u )  DUP PC@ SWAP PC@ 8 LSHIFT OR ;
: READ ( base -- fwd rev )  >R  40 R@ 3 + PC!  80 R@ 3 + PC!  R@ 1+ CNT  R> 2+ CNT ;
: SET-INT ( addr seg int# -- )  4 * >R  0 R@ 2+ L!  0 R> L! ;
: SET-TIMER ( n -- )  FF52 P!  0 FF50 P! ;
: BIOS-TICKS ( -- d )  0 46C L@  0 46E L@ ;
80 INIT-8253  84 INIT-8253
DECIMAL
