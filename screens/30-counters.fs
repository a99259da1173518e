\ Layer 3, position counters: CODE words, as the article wrote them (they
\ run inside the interrupt). Adds CNT-STATE INIT-COUNTERS ?CNT1 ?CNT2, and
\ INSTALL UNINSTALL, which finish layer 2 once INIT-COUNTERS exists.
\ INSTALL is also the way back after INT-OFF, MASK, SET-INT, IS CONTROL or
\ a fault in the tick: it puts RCL's control word back on a running tick.
\ Each 8253's counters 1 and 2 count a wheel's forward and reverse encoder
\ pulses downward; the software extends them to 32 bits.
\ The 80188 assembly of the original is a Python primitive here (CODE
\ binds the name to it and skips the assembler text up to END-CODE).
CODE CNT-STATE  ( -- addr )  per wheel: previous counts, totals. A table
   the counter routines below find by CODE's binding, not by name.
END-CODE  24 ALLOT
CODE INIT-COUNTERS  ( -- )  program both 8253s (counters 0 mode 3,
   counters 1 and 2 mode 2 from 65536), zero the totals.
END-CODE
CODE ?CNT1  ( -- d )  latch counters 1 and 2 of the left 8253, add the
   pulses since the last read to the totals, push forward - reverse.
END-CODE
CODE ?CNT2  ( -- d )  the same for the right wheel (motor 2).
END-CODE

: INSTALL  ( -- )   \ RCL's control word runs every 10 ms from now on
   INT-OFF  STOCK-CONTROL @ ?DUP IF  ['] CONTROL >BODY !  THEN
   USER-TICK GET-INT  2DUP ['] CONTROL GET-CS D= IF 2DROP ELSE OLD-TICK 2! THEN
   ['] CONTROL GET-CS USER-TICK SET-INT  6667 SET-TIMER
   PER-DAY@ 8640000. D= 0= IF  INIT-COUNTERS RCL-RATE  THEN   \ a board not
   INSTALLED ON  UNMASK INT-ON ;       \ yet set up; else counts and time go on
: UNINSTALL  ( -- )   \ back to the BIOS's own tick
   INT-OFF  STOP  OLD-TICK 2@ USER-TICK SET-INT
   36617 SET-TIMER  BIOS-RATE  INSTALLED OFF  INT-ON ;
