\ Layer 2, interrupt control: the 80188's timer 0, the vector table, INSTALL.
\ Adds INT-OFF INT-ON MASK UNMASK SET-TIMER SET-INT GET-INT TICKS@ TICKS!
\ PER-DAY@ PER-DAY! CONTROL STOCK-CONTROL ?TICKING STOCK? RCL-RATE BIOS-RATE
\ (INSTALL itself ends layer 3: it needs the counters). Relies on P! (16-bit
\ OUT, for the 80188's peripheral control block), L@ L! (the 1 MiB address
\ space) and GET-CS.
\ Timer 0 counts 1.5 us periods; the BIOS's
\ type-8 handler counts the time of day at 0040:006C, then runs INT 1Ch.
HEX
FF50 CONSTANT T0-COUNT     FF52 CONSTANT T0-MAX      FF56 CONSTANT T0-CONTROL
FF32 CONSTANT TIMER-MASK   \ bit 3 masks the timer interrupt (requests wait)
C009 CONSTANT T0-QUIET     E009 CONSTANT T0-RUNNING  \ EN INH P CONT, INT off / on
40 CONSTANT BIOS-SEG       6C CONSTANT TICK-COUNT    F0 CONSTANT PER-DAY
1C CONSTANT USER-TICK      \ INT 1Ch, run by the BIOS every tick
DECIMAL

: INT-OFF  ( -- )   T0-QUIET T0-CONTROL P! ;       \ the timer keeps counting
: INT-ON  ( -- )   T0-RUNNING T0-CONTROL P! ;
: SET-TIMER  ( n -- )   T0-MAX P!  0 T0-COUNT P! ; \ period n x 1.5 us
: MASK  ( -- )   8 TIMER-MASK P! ;                 \ hold interrupts (not lose them)
: UNMASK  ( -- )   0 TIMER-MASK P! ;
: SET-INT  ( addr seg int# -- )   4 *  >R  0 R@ 2+ L!  0 R> L! ;
: GET-INT  ( int# -- addr seg )   4 *  >R  0 R@ L@  0 R> 2+ L@ ;

: TICKS@  ( -- d )   \ time of day in ticks; read again if a tick tore it
   BEGIN  BIOS-SEG TICK-COUNT 2+ L@  BIOS-SEG TICK-COUNT L@
          BIOS-SEG TICK-COUNT 2+ L@   ( hi lo hi' )
          ROT OVER = IF EXIT THEN  2DROP
   AGAIN ;
: TICKS!  ( d -- )   MASK  BIOS-SEG TICK-COUNT 2+ L!  BIOS-SEG TICK-COUNT L!  UNMASK ;
: PER-DAY!  ( d -- )   BIOS-SEG PER-DAY 2+ L!  BIOS-SEG PER-DAY L! ;
: PER-DAY@  ( -- d )   BIOS-SEG PER-DAY L@  BIOS-SEG PER-DAY 2+ L@ ;

DEFER CONTROL  ( -- )    \ the 10 ms control word (layer 7 sets it)
VARIABLE STOCK-CONTROL   \ RCL's own control word, which INSTALL puts back
VARIABLE INSTALLED       \ true once INSTALL has run
2VARIABLE OLD-TICK       \ the INT 1Ch vector before INSTALL

\ Every wait of RCL ends by the tick: none may start when no tick can come.
CODE ?TICKING  ( -- )  abort with " Control loop not running " unless timer
   0 interrupts, unmasked, into a Forth word on INT 1Ch.
END-CODE
: STOCK?  ( -- f )   \ RCL's own control word hangs on INT 1Ch
   USER-TICK GET-INT  ['] CONTROL GET-CS D=
   ['] CONTROL >BODY @  STOCK-CONTROL @ =  AND ;

\ After INSTALL the time of day counts 10 ms ticks (8,640,000 a day): the
\ count is rescaled from 36617-count ticks to 6667-count ticks, exactly
\ 36617/6667 = 5 + 3282/6667, so the clock does not jump.
: RCL-RATE  ( -- )
   MASK  TICKS@ 2DUP 5 1 M*/ 2SWAP 3282 6667 M*/ D+  TICKS!
   8640000. PER-DAY!  UNMASK ;
: BIOS-RATE  ( -- )
   MASK  TICKS@ 6667 1 M*/ 36617 MU/MOD ROT DROP TICKS!
   1573040. PER-DAY!  UNMASK ;
