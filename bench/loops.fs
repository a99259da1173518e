\ loops.fs: three nested DO LOOPs doing arithmetic with I and J.
\ 50 x 100 x 200 = 1,000,000 innermost passes of 15 words each.
\ + - * wrap the same way on 16 and 64 bits in their low 16 bits, and the
\ accumulator is masked to 15 bits after every pass, so it is never
\ negative and prints the same everywhere. MOD only sees I >= 0 and 7.
\ Expected output: CHECKSUM 30304

: LOOPS-BENCH  ( -- n )
   0                                     \ acc
   50 0 DO
      100 0 DO
         200 0 DO                        \ here I = inner, J = middle index
            I J * +  I 7 MOD -  J 3 * +  32767 AND
         LOOP
      LOOP
   LOOP ;

: REPORT  ( n -- )  CR ." CHECKSUM " . CR ;

LOOPS-BENCH REPORT
