\ Layer 7, motion planning: the trapezoid, from units to counts and speeds.
\ Adds DISTANCE COUNTS EXPECTED SPEED >REF DSQRT BREAKPOINTS ACC-END
\ DEC-START MOVE-END PEAK V-CREEP RUN-ON. Relies on layers 4 to 6.
\ Units inside: speeds in crpm (0.01 rpm of the wheel), distances in
\ ten-thousandths of an inch (DISTANCE) or encoder counts (everything else);
\ rounding is half away from zero.
600 CONSTANT V-CREEP     \ crpm: the slowest speed of a deceleration (1.76 in/s)
2 CONSTANT RUN-ON        \ counts a wheel rolls on after its relays open

: DISTANCE  ( c0 c1 -- d4 )   \ inches x 10^4 to go from speed c0 to c1 at ACCEL
   DUP UM* ROT DUP UM* D- DABS           ( |c1^2 - c0^2| )
   11 ACCEL @ M*/  1 75 R*/ ;
: COUNTS  ( d4 -- d )   1 352 R*/ ;      \ inches x 10^4 to encoder counts
: EXPECTED  ( -- d )   \ the pending distance in counts (each wheel's travel)
   PENDING 2@ PENDING-UNIT @ COUNT-RATIOS RATIO R*/ ;

CREATE SPEED-RATIOS   3 , 5 ,   3 , 88 ,   9 , 22 ,   3 , 440 ,
: SPEED  ( -- c )   \ the base's maximum speed in crpm, 1 to 30000
   SPEED-V4 2@ SPEED-UNIT @ SPEED-RATIOS RATIO R*/
   30000. DMIN DROP 1 MAX ;
: (>REF)  ( c -- u )   \ round(1,500,000 / c) for 1 <= c <= 30000 (CONTROL's)
   >R 3000000. R@ 0 D+ R> 2* UM/MOD NIP ;
\ Below 23 crpm the count would pass 65536: UM/MOD's no-trap overflow
\ (F83) gives 65535 then, as good as the slowest count. The word for
\ users keeps the count within 50 (5 MPH) and 65536, written as 0.
: >REF  ( c -- u )   \ 8253 count for speed c crpm
   DUP 23 U< IF DROP 0 EXIT THEN  DUP 30000 U> IF DROP 30000 THEN  (>REF) ;

: DSQRT  ( ud -- u )   \ integer square root: Newton's method from above
   65535 BEGIN                         ( ud x )
      >R 2DUP R@ UM/MOD NIP            ( ud ud/x ) ( R: x )
      0 R@ 0 D+ D2/ DROP               ( ud x' )
      DUP R@ U< WHILE  R> DROP
   REPEAT  DROP R> NIP NIP ;

\ The move's profile. Both wheels of a base move run the same trapezoid,
\ so one profile serves both: the article's per-motor "arrays" below
\ answer with the same place for either motor.
2VARIABLE ACC-AT   2VARIABLE DEC-AT   2VARIABLE END-AT   VARIABLE TOP-SPEED
2VARIABLE ARRIVE-AT      \ END-AT less RUN-ON: where a wheel is stopped
: ACC-END  ( motor# -- addr )   DROP ACC-AT ;
: DEC-START  ( motor# -- addr )   DROP DEC-AT ;
: MOVE-END  ( motor# -- addr )   DROP END-AT ;
: PEAK  ( motor# -- addr )   DROP TOP-SPEED ;

2VARIABLE RAMP       \ counts to accelerate (and to decelerate)
2VARIABLE HALF       \ half the move
VARIABLE TOP         \ crpm at the end of the ramp
: PROFILE  ( dtotal c -- )   \ RAMP and TOP for a move of dtotal counts
   DUP TOP !  >R  D2/ HALF 2!                    ( ) ( R: c )
   0 R@ DISTANCE COUNTS                          ( dfull )
   2DUP HALF 2@ D> IF     \ no room for the full ramp: a triangle
      2DROP  HALF 2@ RAMP 2!
      HALF 2@ 2400 1 M*/ ACCEL @ 1 M*/ DSQRT R@ MIN TOP !
   ELSE  RAMP 2!  THEN
   TOP @  R> V-CREEP MIN  MAX TOP ! ;            \ never below min(c, V-CREEP)
: BREAKPOINTS  ( dtotal c -- )   \ fill both motors' arrays for the move
   >R 2DUP R> PROFILE
   2DUP END-AT 2!  2DUP RUN-ON 0 D- ARRIVE-AT 2!
   RAMP 2@ ACC-AT 2!  RAMP 2@ D- DEC-AT 2!  TOP @ TOP-SPEED ! ;
