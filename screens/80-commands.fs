\ Layer 8, command language: [DEVICE] [n SPEED] [n DISTANCE] COMMAND.
\ Adds RERB ARM FORWARD BACKWARD LEFT RIGHT UP DOWN OPEN CLOSE, and under
\ them DEVICE LAST-DISTANCE TAKE ?CONTROL ?SETTINGS STALL? AWAIT (MOVE)
\ (ARM-MOVE) (SAFE). Relies on layers 1-7.
\ Optional parameters (docs/guide.md section 4): a distance waits in
\ PENDING for the next command; with none, a command reuses its own last
\ distance, first its default. Speed and G persist until changed.
VARIABLE DEVICE   1 DEVICE !     \ 1 the base (RERB), 2 the arm
: RERB  ( -- )   1 DEVICE ! ;    \ "R-E Robot Base"
: ARM  ( -- )   2 DEVICE ! ;   \ select the arm and gripper

\ Commands: 0 FORWARD 1 BACKWARD 2 LEFT 3 RIGHT 4 UP 5 DOWN 6 OPEN 7 CLOSE.
\ Each keeps its last distance: V4 (a double) and unit, 6 bytes.
CREATE LASTS  48 ALLOT
: LAST-DISTANCE  ( cmd# -- addr )   6 * LASTS + ;
: DEFAULT  ( V4 unit cmd# -- )   LAST-DISTANCE >R  R@ 4 + !  R> 2! ;
 10000. 2 0 DEFAULT   10000. 2 1 DEFAULT      \ 1 FEET
900000. 4 2 DEFAULT  900000. 4 3 DEFAULT      \ 90 DEGREES
 10000. 1 4 DEFAULT   10000. 1 5 DEFAULT      \ 1 INCHES
 30000. 1 6 DEFAULT   30000. 1 7 DEFAULT      \ 3 INCHES: full jaw travel
: TAKE  ( cmd# -- )   \ PENDING: the distance given, else the last one
   LAST-DISTANCE  PENDING-UNIT @ IF
      PENDING 2@ 2 PICK 2!  PENDING-UNIT @ SWAP 4 + !
   ELSE  DUP 2@ PENDING 2!  4 + @ PENDING-UNIT !  THEN ;

\ The layer-1 relay words by direction, before FORWARD becomes a command.
CREATE RELAY-WORDS   ' FORWARD ,  ' REVERSE ,  ' CCW ,  ' CW ,
CREATE SIGNS   1 , 1 ,   -1 , -1 ,   -1 , 1 ,   1 , -1 ,   \ left, right
: START  ( dir -- )   \ both wheels set off on a new move
   4 * SIGNS +  DUP @ WHEEL1 >DIR + !  2+ @ WHEEL2 >DIR + !
   WHEEL1 READ-POS WHEEL1 >START + 2!  WHEEL2 READ-POS WHEEL2 >START + 2!
   0. Q-AT 2!  Q-PART OFF  N-PART OFF  1 N-NOW !  0 SPEED-NOW !  SPEED-HELD OFF  BOTH ON
   WHEEL1 >MOVING + ON  WHEEL2 >MOVING + ON ;

DEFER MOVED  ( -- )   \ after each base move (the status layer's odometry)
' NOOP IS MOVED

\ A command waits for the control loop to finish it, so it starts only if
\ the loop can run, with settings its checks can work with, and gives up
\ (everything stopped) if the loop stops making progress: no wait lasts
\ forever with a motor on.
: ?CONTROL  ( -- )   \ RCL's control word can run every tick
   INSTALLED @ 0= ABORT" Not installed"  ?TICKING
   USER-TICK GET-INT ['] CONTROL GET-CS D= 0=
   ABORT" INT 1Ch is not CONTROL (INSTALL puts it back)" ;
: ?SETTINGS  ( -- )   \ a trapezoid that climbs, a lag that can trip
   ACCEL @ 1 30001 WITHIN 0= ABORT" Bad acceleration"
   FERR-LIMIT @ 1 30001 WITHIN 0= ABORT" Bad following limit" ;
100 CONSTANT PATIENCE    \ waits (ticks, when they come) without progress
: STALL?  ( x1 x2 n -- n' )   \ count the waits in which progress x stood still
   -ROT = IF  1+ DUP PATIENCE > ABORT" Control loop stalled"  ELSE DROP 0 THEN ;
: AWAIT  ( busy 'progress -- )   \ HALT while busy @, progress watched
   0 BEGIN  2 PICK @ WHILE  OVER EXECUTE HALT  2 PICK EXECUTE ROT STALL?  REPEAT
   DROP 2DROP ;
: MOVE-PROGRESS  ( -- x )   Q-AT 2+ @ Q-PART @ + ;   \ q in crpm-ticks, folded
: WAIT-MOVE  ( -- )   MOVING ['] MOVE-PROGRESS AWAIT ;
: (MOVE)  ( dir -- )   \ 0 forward 1 backward 2 left 3 right
   ?CONTROL ?SETTINGS
   RERB  DUP TAKE  EXPECTED  PENDING-UNIT OFF        ( dir d )
   2DUP D0< IF DNEGATE ROT 1 XOR -ROT THEN           \ negative: the other way
   2DUP D0= IF 2DROP DROP EXIT THEN
   SPEED BREAKPOINTS                                 ( dir )
   COAST  DUP 2* RELAY-WORDS + @ EXECUTE  START
   FERR OFF  MOVING ON  GO  WAIT-MOVE
   COAST STOP  MOVED  FERR @ ABORT" Following error" ;

\ Arm commands: relay bits, the STATUS bit that ends them, ticks an inch
\ (lift 1 in/s, jaws 0.5 in/s), and the command that goes the other way.
CREATE ARM-MOVES
   ARM-ON ,                  1 ,  100 ,  5 ,     \ UP     until ARM-TOP
   ARM-ON ARM-DOWN OR ,      2 ,  100 ,  4 ,     \ DOWN   until ARM-BOTTOM
   GRIP-ON ,                 4 ,  200 ,  7 ,     \ OPEN   until GRIP-OPENED
   GRIP-ON GRIP-CLOSE OR ,   8 ,  200 ,  6 ,     \ CLOSE  until GRIP-CLOSED
: ARM-MOVE  ( cmd# -- addr )   4 - 8 * ARM-MOVES + ;
: ARM-TICKS  ( cmd# -- ticks )   \ the pending distance as ticks of that motor
   >R  PENDING 2@  PENDING-UNIT @ 2 = IF 12 ELSE 1 THEN   ( d inches-per-unit )
   R> ARM-MOVE 4 + @ *  10000 R*/ DROP ;
: ARM-PROGRESS  ( -- x )   ARM-BUDGET @ ;
: WAIT-ARM  ( -- )   ARM-BITS ['] ARM-PROGRESS AWAIT ;
: (ARM-MOVE)  ( cmd# -- )   \ 4 up 5 down 6 open 7 close
   ?CONTROL
   ARM  PENDING-UNIT @ 2 > ABORT" Bad unit"          \ INCHES or FEET only
   DUP TAKE  PENDING 2@ D0< IF                       \ negative: the other way
      PENDING 2@ DNEGATE PENDING 2!  ARM-MOVE 6 + @
   THEN
   DUP ARM-TICKS  PENDING-UNIT OFF  ?DUP 0= IF DROP EXIT THEN
   SWAP ARM-MOVE                                      ( ticks entry )
   SENSORS@ OVER 2+ @ AND IF 2DROP EXIT THEN          \ already at that limit
   DUP 2+ @ ARM-LIMIT !  SWAP ARM-BUDGET !  @ DUP ENABLE ARM-BITS !
   WAIT-ARM ;

\ After any error or Ctrl-C (the kernel's SAFE-STATE): every relay open,
\ no move under way, no distance pending.
: (SAFE)  ( -- )
   RELAYS OFF LATCH  MOVING OFF  WHEEL1 >MOVING + OFF  WHEEL2 >MOVING + OFF
   ARM-BITS OFF  PENDING-UNIT OFF ;

: FORWARD  ( -- )   0 (MOVE) ;   \ drive ahead the distance (default 1 FEET)
: BACKWARD  ( -- )   1 (MOVE) ;   \ drive back the distance (default 1 FEET)
: LEFT  ( -- )   2 (MOVE) ;       \ spin counter-clockwise in place
: RIGHT  ( -- )   3 (MOVE) ;      \ spin clockwise
: UP  ( -- )   4 (ARM-MOVE) ;   \ raise the arm by the distance (default 1 INCHES)
: DOWN  ( -- )   5 (ARM-MOVE) ;   \ lower the arm by the distance (default 1 INCHES)
: OPEN  ( -- )   6 (ARM-MOVE) ;    \ relative to where the jaws are
: CLOSE  ( -- )   7 (ARM-MOVE) ;   \ stops early on an object
