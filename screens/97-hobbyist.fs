\ Hobbyist's words, not the article's: metric units, faults, a pose reset.
\ Adds CM METERS MM CM/S (CM) (METERS) (MM) (CM/S) STALL-LEFT STALL-RIGHT
\ UNSTALL LOAD-LEFT LOAD-RIGHT ENCODER-LEFT-OFF ENCODER-RIGHT-OFF NO-FAULTS
\ HOME-POSE .POSE-METRIC UR*/ METRIC>INCHES FAULT!.
\ Relies on layers 5 to 9 and the status words. None of these is in the
\ 1986 article; its words are untouched (this layer only adds words).
\ Loaded on demand, INCLUDE 97-hobbyist.fs, not by rcl.fs: the time its
\ loading takes would start the control loop later against the 8253s'
\ own clocks, and change every simulated run of the article by a count.
\ A metric distance or speed is kept as the article's INCHES or IPS value
\ nearest to it that gives exactly the metric count: with 1 in = 2.54 cm
\ and 625/22 counts an inch, counts = round(V4 x n / 44704) for V4 in
\ ten-thousandths of the unit, n = 5 MM, 50 CM, 5000 METERS (so 100 CM is
\ 1118 counts, as 39.3701 INCHES is), and crpm = round(V4 x 75 / 5588) for
\ CM/S (10 CM/S is 1342 crpm, as 3.937 IPS is).

\ d x n1 / u2 rounded half away from zero, as R*/ (layer 5) but for a
\ divisor up to 65535 (R*/ halves its divisor with the signed 2/).
: UR*/  ( d n1 u2 -- d' )   \ d x n1 / u2 rounded, u2 up to 65535
   >R >R  2DUP D0< -ROT DABS              ( sign ud ) ( R: u2 n1 )
   R> UT*  R@ U2/ UT+  R> UT/               ( sign q0 q1 q2 )
   OVER 0< OR ABORT" Out of range"
   ROT IF DNEGATE THEN ;
\ The inches V4 of a metric V4 (n as above): V4 x n / 127 rounded, moved
\ one ten-thousandth back if the two roundings ended on another count.
: METRIC>INCHES  ( d n -- d' )   \ a metric V4 as the INCHES V4 of the same counts
   >R 2DUP R@ 44704 UR*/  2SWAP R> 127 R*/   ( counts v4in )
   2DUP 1 352 R*/  2ROT 2SWAP D- D+ ;       \ v4in + (counts - its counts)
: INCHES!  ( d -- )   PENDING 2!  1 PENDING-UNIT ! ;   \ a V4 in inches, pending
: (MM)  ( fx -- )   >V4 5 METRIC>INCHES INCHES! ;   \ MM of a FIXED pair
: (CM)  ( fx -- )   >V4 50 METRIC>INCHES INCHES! ;   \ CM of a FIXED pair
: (METERS)  ( fx -- )   >V4 5000 METRIC>INCHES INCHES! ;   \ METERS of a FIXED pair
: MM  ( num -- )   FIXED (MM) ;   \ the distance for the next command, in millimetres
: CM  ( num -- )   FIXED (CM) ;   \ the distance for the next command, in centimetres
: METERS  ( num -- )   FIXED (METERS) ;   \ the distance for the next command, in metres

\ A speed: the IPS V4 nearest V4 x 50 / 127 that gives round(V4 x 75 / 5588)
\ crpm; a speed too small for that is the least IPS (1 crpm, as IPS gives).
: (CM/S)  ( fx -- )   \ CM/S of a FIXED pair
   POSITIVE ABORT" Bad speed"
   2DUP 75 5588 R*/  2SWAP 50 127 R*/       ( crpm v4ips )
   2DUP 3 88 R*/  2ROT 2SWAP D- D+  1. DMAX
   SPEED-V4 2!  2 SPEED-UNIT ! ;
: CM/S  ( num -- )   FIXED (CM/S) ;   \ the base's top speed, centimetres a second

\ Faults on the simulated board, as its Python API and rcl-board inject
\ them; a real board refuses each (its faults are real).
CODE FAULT!  ( x wheel# fault# -- )  put a fault on the simulated board
   (wheel# 0 left, 1 right; fault# 0 stall, x a flag; 1 load, x 0 to 100
   percent; 2 encoder, x false: it stops counting), via inject_fault.
END-CODE
: STALL-LEFT  ( -- )   -1 0 0 FAULT! ;   \ the left wheel is blocked: its motor turns no more
: STALL-RIGHT  ( -- )   -1 1 0 FAULT! ;   \ the right wheel is blocked
: UNSTALL  ( -- )   0 0 0 FAULT!  0 1 0 FAULT! ;   \ both wheels turn again
: LOAD-LEFT  ( percent -- )   0 1 FAULT! ;   \ a drag on the left wheel, % of its torque
: LOAD-RIGHT  ( percent -- )   1 1 FAULT! ;   \ a drag on the right wheel, % of its torque
: ENCODER-LEFT-OFF  ( -- )   0 0 2 FAULT! ;   \ the left encoder stops counting
: ENCODER-RIGHT-OFF  ( -- )   0 1 2 FAULT! ;   \ the right encoder stops counting
: NO-FAULTS  ( -- )   \ no stall, no load, both encoders counting
   UNSTALL  0 LOAD-LEFT  0 LOAD-RIGHT  -1 0 2 FAULT!  -1 1 2 FAULT! ;

\ RCL's dead-reckoned pose (the status words) back to the origin.
: HOME-POSE  ( -- )   \ the pose is 0,0 heading 0 from here; nothing moves
   ODOMETRY  0. POSE-X 2!  0. POSE-Y 2!  POSE-HEADING OFF ;
: .POSE-METRIC  ( -- )   \ x and y in centimetres, heading in degrees
   ODOMETRY  ." x " POSE-X 2@ 127 500 R*/ .HUNDREDTHS  ."  cm  y " POSE-Y 2@ 127 500 R*/
   .HUNDREDTHS  ."  cm  heading " POSE-HEADING @ 0 <# # [CHAR] . HOLD #S #> TYPE ."  deg " ;
