\ Layer 6, user-input conversion: distance, speed and acceleration units.
\ Adds INCHES FEET MILES DEGREES (and their (FIXED-pair) forms), PENDING,
\ MPH IPS FPS FPM G (and their parenthesised forms), ACCEL. Relies on
\ layer 5. Each plain word is FIXED then its parenthesised partner, which
\ takes an already converted FIXED pair (Listing 2 uses (FEET)).
\ A distance waits in PENDING for the next command (the optional-parameter
\ rule, docs/guide.md section 4). Units: 1 INCHES 2 FEET 3 MILES 4 DEGREES.
2VARIABLE PENDING        \ V4 of the distance given, if PENDING-UNIT is set
VARIABLE PENDING-UNIT    \ 0: none pending
: DISTANCE!  ( fx unit -- )   >R >V4 PENDING 2! R> PENDING-UNIT ! ;
: (INCHES)  ( fx -- )   1 DISTANCE! ;
: (FEET)  ( fx -- )   2 DISTANCE! ;
: (MILES)  ( fx -- )   3 DISTANCE! ;
: (DEGREES)  ( fx -- )   4 DISTANCE! ;   \ each wheel's arc, 11/90 in a degree
: INCHES  ( num -- )   FIXED (INCHES) ;   \ the distance for the next command, in inches
: FEET  ( num -- )   FIXED (FEET) ;   \ the distance for the next command, in feet
: MILES  ( num -- )   FIXED (MILES) ;   \ the distance for the next command, in miles
: DEGREES  ( num -- )   FIXED (DEGREES) ;   \ the turn for the next command, in degrees

\ Counts = round(V4 x num / den): INCHES 1/352,
\ FEET 3/88, MILES 180/1, DEGREES 1/2880.
CREATE COUNT-RATIOS   1 , 352 ,   3 , 88 ,   180 , 1 ,   1 , 2880 ,
: RATIO  ( unit table -- num den )   SWAP 1- 4 * + 2@ SWAP ;

\ The base's speed: V4 and unit, 1 MPH 2 IPS 3 FPS 4 FPM (default 1 MPH).
2VARIABLE SPEED-V4   10000. SPEED-V4 2!
VARIABLE SPEED-UNIT   1 SPEED-UNIT !
: POSITIVE  ( fx -- d f )   >V4 2DUP D0< >R 2DUP D0= R> OR ;
: SPEED!  ( fx unit -- )   >R POSITIVE ABORT" Bad speed"  SPEED-V4 2! R> SPEED-UNIT ! ;
: (MPH)  ( fx -- )   1 SPEED! ;
: (IPS)  ( fx -- )   2 SPEED! ;
: (FPS)  ( fx -- )   3 SPEED! ;
: (FPM)  ( fx -- )   4 SPEED! ;
: MPH  ( num -- )   FIXED (MPH) ;   \ the base's top speed, miles an hour
: IPS  ( num -- )   FIXED (IPS) ;   \ the base's top speed, inches a second
: FPS  ( num -- )   FIXED (FPS) ;   \ the base's top speed, feet a second
: FPM  ( num -- )   FIXED (FPM) ;   \ the base's top speed, feet a minute

\ G: accelerations are kept as crpm per 10 ms tick, converted at once:
\ ACCEL = max(1, round(V4 x 1449 / 11000)), so 0.1 G is 132 (docs/guide.md 13).
VARIABLE ACCEL   132 ACCEL !
: (G)  ( fx -- )
   POSITIVE ABORT" Bad acceleration"
   1449 11000 R*/  30000. 2OVER D< ABORT" Bad acceleration"
   DROP 1 MAX ACCEL ! ;
: G  ( num -- )   FIXED (G) ;   \ the base's acceleration, in G (default 0.1)
