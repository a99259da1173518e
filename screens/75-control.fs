\ Layer 7, continued: the 10 ms control word that INSTALL hangs on INT 1Ch.
\ Adds MOVING SPEED-NOW Q-AT Q-PART N-PART N-NOW ARM-BITS ARM-BUDGET
\ ARM-LIMIT COMMANDED ADVANCE NEW-SPEED SET-SPEED CHECK-WHEEL ARM-TICK
\ (CONTROL). Relies on layers 1 to 7. Each tick:
\   the commanded progress q (Q-AT, where the 8253 counts sent so far have
\   told the wheels to be); the speed steps along the trapezoid laid out on
\   q and its 8253 count goes out first, so the wheels get it with the
\   least delay; ADVANCE adds to q exactly what that count makes the wheels
\   travel in a tick, 1250.0625/N counts, remainders kept (the article's
\   EXPACC, the sum of the speeds, over 1200), so a healthy wheel never
\   drifts from q however long the move, and q never wraps within 32-bit
\   counts.
\   Then each moving wheel's position p: |q - p| > FERR-LIMIT stops
\   everything (following error); p at the end (less RUN-ON) stops that
\   wheel. When both are done the move is over. Last, the arm's ticks.
\ Both wheels share the speed: they run the same profile until they stop.
VARIABLE MOVING      \ a base move is under way
VARIABLE SPEED-NOW   \ crpm commanded now
VARIABLE N-NOW       \ the 8253 count sent last
VARIABLE BOTH        \ both wheels still moving
VARIABLE SPEED-HELD  \ a wheel stopped this tick: the other keeps its speed
2VARIABLE Q-AT       \ q: counts the wheels have been told to travel
VARIABLE Q-PART      \ crpm-ticks toward q's next count (0 to 1199)
VARIABLE N-PART      \ 1/N crpm-ticks toward Q-PART's next (0 to N-1)
VARIABLE ARM-BITS    \ relay bits of the arm or gripper move under way, or 0
VARIABLE ARM-BUDGET  \ ticks left for it
VARIABLE ARM-LIMIT   \ the STATUS bit that ends it early

: COMMANDED  ( -- dq )   Q-AT 2@ ;
: EXPECTED-POS  ( motor# -- d )   DROP COMMANDED ;
\ Count N (50..65535, from >REF) makes 125,000 / N encoder counts a second.
\ A tick is 6667 x 1.5 us = 10.0005 ms (not 10), so in a tick the wheel
\ goes 1,500,075 / N crpm-ticks (1/1200 count each; 1,500,000 would let q
\ fall 5 counts in 100,000 behind a healthy wheel, a false following error
\ after two miles). A quotient and a remainder in 1/N crpm-tick: the
\ remainders add up in N-PART and carry. When the
\ count changes, N-PART is rescaled to the new 1/N (losing less than 1/N of
\ a crpm-tick): exact while the speed holds, and within a count over the
\ longest ramp.
: ADVANCE  ( N -- )   \ q moves on by one tick at count N
   DUP N-NOW @ <> IF                                   \ N-PART x N / N-NOW
      DUP N-PART @ UM*  N-NOW @ UM/MOD NIP  N-PART !  DUP N-NOW !
   THEN
   >R  1500075. R@ UM/MOD SWAP                         ( quot rem ) ( R: N )
   N-PART @  R> 2 PICK -                               ( quot rem part N-rem )
   2DUP U< IF  DROP +  ELSE  - NIP  SWAP 1+ SWAP  THEN ( quot' part' )
   N-PART !  Q-PART @ +  1200 /MOD  SWAP Q-PART !  Q-AT 2@ ROT M+ Q-AT 2! ;
: NEW-SPEED  ( dq -- v )   \ the speed at commanded progress q
   2DUP ACC-AT 2@ D< IF  2DROP SPEED-NOW @ ACCEL @ + TOP-SPEED @ MIN  EXIT THEN
   DEC-AT 2@ D< IF  TOP-SPEED @  EXIT THEN
   SPEED-NOW @ ACCEL @ -  V-CREEP TOP-SPEED @ MIN  MAX ;
: SEND  ( u port -- )   >R  DUP 255 AND R@ PC!  8 RSHIFT R> PC! ;
: SET-SPEED  ( v -- )   \ command speed v to the moving wheels
   DUP SPEED-NOW !  (>REF)
   BOTH @ IF                             \ both: LSBs, then MSBs
      DUP 255 AND DUP LEFT-8253 PC! RIGHT-8253 PC!
      DUP 8 RSHIFT DUP LEFT-8253 PC! RIGHT-8253 PC!
   ELSE  WHEEL1 @ IF DUP LEFT-8253 SEND THEN  WHEEL2 @ IF DUP RIGHT-8253 SEND THEN
   THEN  ADVANCE ;
: STOPPED  ( rec -- )   \ this wheel has arrived: its relays off (braked);
   \ one MOTOR latch write, as STOP-LEFT or STOP-RIGHT would make it
   >R  R@ >KEEP + @ RELAYS @ AND DUP RELAYS ! MOTOR-PORT PC!
   R> >MOVING + OFF  BOTH OFF  SPEED-HELD ON
   WHEEL1 @ WHEEL2 @ OR 0= IF MOVING OFF THEN ;
: FOLLOWING-ERROR  ( rec -- )   \ it cannot follow: stop everything
   DUP WHEEL1 = IF 1 ELSE 2 THEN FERR !  DROP  STOP
   WHEEL1 >MOVING + OFF  WHEEL2 >MOVING + OFF  MOVING OFF ;
: CHECK-WHEEL  ( dq rec -- dq )   \ a moving wheel against q: lag, arrival
   >R  R@ >COUNTER + @ EXECUTE                 ( dq dpos ) ( R: rec )
   R@ 2+ 2@ D-  R@ >DIR + @ ?DNEGATE           ( dq dp ) \ 2+ is >START
   2OVER 2OVER D- DROP ABS FERR-LIMIT @ > IF 2DROP R> FOLLOWING-ERROR EXIT THEN
   ARRIVE-AT 2@ D< IF R> DROP EXIT THEN
   R> STOPPED ;
: ARM-TICK  ( -- )   \ the arm or gripper runs out its ticks, or meets its limit
   -1 ARM-BUDGET +!
   ARM-BUDGET @ 0= SENSORS@ ARM-LIMIT @ AND OR IF
      ARM-BITS @ DISABLE  ARM-BITS OFF
   THEN ;
\ Written for its cost, one primitive at a time (27.8 us each): with both
\ wheels moving a tick must stay under half of its 10 ms. So the tick
\ that stops one wheel does not also step the other's speed: that wheel
\ keeps its speed (and q its step) one tick longer, 0.1 count at
\ 0.1 G. Arm moves never overlap base moves (commands wait), so the arm
\ is looked after in the ticks between base moves.
: (CONTROL)  ( -- )   \ the control word, every 10 ms
   MOVING @ IF
      Q-AT 2@                                   ( dq )
      WHEEL1 @ IF WHEEL1 CHECK-WHEEL THEN
      WHEEL2 @ IF WHEEL2 CHECK-WHEEL THEN
      SPEED-HELD @ IF  SPEED-HELD OFF 2DROP  N-NOW @ ADVANCE  EXIT THEN
      MOVING @ IF NEW-SPEED SET-SPEED ELSE 2DROP THEN
   ELSE                                          \ between moves: lean
      ?CNT1 POS1 2!  ?CNT2 POS2 2!
      ARM-BITS @ IF ARM-TICK THEN
   THEN ;
' (CONTROL) DUP IS CONTROL  STOCK-CONTROL !
