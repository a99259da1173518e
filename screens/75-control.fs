\ Layer 7, continued: the 10 ms control word that INSTALL hangs on INT 1Ch.
\ Adds MOVING SPEED-NOW EXPACC ARM-BITS ARM-BUDGET ARM-LIMIT
\ COMMANDED STEP NEW-SPEED SET-SPEED CHECK-WHEEL ARM-TICK (CONTROL).
\ Relies on layers 1 to 7. Each tick (rcl-words.md section 6):
\   the commanded progress q = EXPACC / 1200 (where the 8253 counts sent so
\   far have told the wheels to be); the speed steps along the trapezoid
\   laid out on q and its 8253 count goes out first, so the wheels get it
\   with the least delay; EXPACC adds the speed that count really makes.
\   Then each moving wheel's position p: |q - p| > FERR-LIMIT stops
\   everything (following error); p at the end (less RUN-ON) stops that
\   wheel. When both are done the move is over. Last, the arm's ticks.
\ Both wheels share the speed: they run the same profile until they stop.
VARIABLE MOVING      \ a base move is under way
VARIABLE SPEED-NOW   \ crpm commanded now
VARIABLE STEP-NOW    \ the crpm its 8253 count really makes (EXPACC's step)
VARIABLE BOTH        \ both wheels still moving
VARIABLE SPEED-HELD  \ a wheel stopped this tick: the other keeps its speed
2VARIABLE EXPACC     \ the sum of the speeds commanded, tick by tick (crpm)
VARIABLE ARM-BITS    \ relay bits of the arm or gripper move under way, or 0
VARIABLE ARM-BUDGET  \ ticks left for it
VARIABLE ARM-LIMIT   \ the STATUS bit that ends it early

: COMMANDED  ( -- dq )   EXPACC 2@ 1200 MU/MOD ROT DROP ;
: EXPECTED-POS  ( motor# -- d )   DROP COMMANDED ;
: STEP  ( N -- u )   \ the crpm 8253 count N (50..65535, from >REF) really
   DUP >R 2/ 0 1500000. D+ R> UM/MOD NIP ;   \ makes: round(1,500,000 / N)
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
   THEN  STEP DUP STEP-NOW !  0 EXPACC 2@ D+ EXPACC 2! ;
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
\ keeps its speed (and EXPACC its step) one tick longer, 0.1 count at
\ 0.1 G. Arm moves never overlap base moves (commands wait), so the arm
\ is looked after in the ticks between base moves.
: (CONTROL)  ( -- )   \ the control word, every 10 ms
   MOVING @ IF
      EXPACC 2@ 1200 MU/MOD ROT DROP            ( dq )
      WHEEL1 @ IF WHEEL1 CHECK-WHEEL THEN
      WHEEL2 @ IF WHEEL2 CHECK-WHEEL THEN
      SPEED-HELD @ IF  SPEED-HELD OFF 2DROP  STEP-NOW @ 0 EXPACC 2@ D+ EXPACC 2!  EXIT THEN
      MOVING @ IF NEW-SPEED SET-SPEED ELSE 2DROP THEN
   ELSE                                          \ between moves: lean
      ?CNT1 POS1 2!  ?CNT2 POS2 2!
      ARM-BITS @ IF ARM-TICK THEN
   THEN ;
' (CONTROL) IS CONTROL
