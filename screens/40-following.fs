\ Layer 4, following error: each wheel's part of a move, and the limit.
\ Adds WHEEL1 WHEEL2 >WHEEL (and their fields) POS1 POS2 FERR-LIMIT FERR
\ READ-POS. Relies on layers 1 and 3.
\ A wheel's record (offsets in bytes; doubles take 4):
\   >MOVING flag   >START d   >DIR +1 or -1   >POS d (last read)
\   >PORT its 8253   >COUNTER xt of ?CNT1 or ?CNT2   >KEEP the relay bits
\   left when it stops (the complement of its ON and GO bits)
 0 CONSTANT >MOVING    2 CONSTANT >START   6 CONSTANT >DIR
 8 CONSTANT >POS      12 CONSTANT >PORT   14 CONSTANT >COUNTER
16 CONSTANT >KEEP     18 CONSTANT /WHEEL
: WHEEL:  ( port 'counter keep -- )   \ define a wheel's record
   CREATE HERE /WHEEL ALLOT  DUP /WHEEL ERASE
   TUCK >KEEP + !  TUCK >COUNTER + !  >PORT + ! ;
LEFT-8253 ' ?CNT1 M1-ON M1-GO OR NOT WHEEL: WHEEL1      \ motor 1, the left wheel
RIGHT-8253 ' ?CNT2 M2-ON M2-GO OR NOT WHEEL: WHEEL2     \ motor 2, the right wheel
: >WHEEL  ( motor# -- rec )   1 = IF WHEEL1 ELSE WHEEL2 THEN ;
WHEEL1 >POS + CONSTANT POS1   \ ( -- addr ) the positions read last
WHEEL2 >POS + CONSTANT POS2

VARIABLE FERR-LIMIT   100 FERR-LIMIT !    \ counts (3.5 in) of allowed lag
VARIABLE FERR         \ 0 none, else the motor# that could not follow

: READ-POS  ( rec -- d )   \ read the wheel's counters now, and keep it
   >R  R@ >COUNTER + @ EXECUTE  2DUP R> >POS + 2! ;
\ The check itself, |q - p| > FERR-LIMIT for each moving wheel, is made by
\ CHECK-WHEEL in the control word (layer 7), written inline there to fit
\ the 10 ms tick; FERR-LIMIT and FERR are its limit and its flag.
