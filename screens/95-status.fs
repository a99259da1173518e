\ Status words: where the robot is by its wheels' counts, and the settings.
\ Adds POSE-X POSE-Y POSE-HEADING ODOMETRY .POSE .SETTINGS. Relies on layers 1-9.
\ Dead reckoning after each base move (and at .POSE): from the counts the
\ wheels moved since the last time, a straight move or a spin (the only
\ moves RCL makes; a wheel's run-on after a move counts with it). Position in
\ thousandths of an inch, heading in tenths of a degree, 0 to 3599.
2VARIABLE POSE-X   2VARIABLE POSE-Y   VARIABLE POSE-HEADING
2VARIABLE ODO-L   2VARIABLE ODO-R    \ the counts the pose was last brought to
CREATE SINES    \ sin of 0 to 90 degrees, x 10000
   0 , 175 , 349 , 523 , 698 , 872 , 1045 , 1219 , 1392 , 1564 , 1736 , 1908 , 2079 ,
   2250 , 2419 , 2588 , 2756 , 2924 , 3090 , 3256 , 3420 , 3584 , 3746 , 3907 , 4067 , 4226 ,
   4384 , 4540 , 4695 , 4848 , 5000 , 5150 , 5299 , 5446 , 5592 , 5736 , 5878 , 6018 , 6157 ,
   6293 , 6428 , 6561 , 6691 , 6820 , 6947 , 7071 , 7193 , 7314 , 7431 , 7547 , 7660 , 7771 ,
   7880 , 7986 , 8090 , 8192 , 8290 , 8387 , 8480 , 8572 , 8660 , 8746 , 8829 , 8910 , 8988 ,
   9063 , 9135 , 9205 , 9272 , 9336 , 9397 , 9455 , 9511 , 9563 , 9613 , 9659 , 9703 , 9744 ,
   9781 , 9816 , 9848 , 9877 , 9903 , 9925 , 9945 , 9962 , 9976 , 9986 , 9994 , 9998 , 10000 ,
: SIN90  ( tenths -- n )   10 /MOD 2* SINES +  DUP @ SWAP 2+ @ OVER -  ROT 10 */ + ;
: SIN  ( tenths -- n )   \ any angle in tenths of a degree, x 10000
   3600 MOD  DUP 1800 < IF 1 ELSE 1800 - -1 THEN SWAP
   DUP 900 > IF 1800 SWAP - THEN  SIN90 * ;
: COS  ( tenths -- n )   900 + SIN ;
: SCALED  ( d n -- d' )   \ d x n / 10000, n signed
   DUP 0< IF NEGATE >R DNEGATE R> THEN 10000 R*/ ;
: ODOMETRY  ( -- )   \ the wheels' travel since the last time, into the pose
   ?CNT1 2DUP ODO-L 2@ D- 2SWAP ODO-L 2!
   ?CNT2 2DUP ODO-R 2@ D- 2SWAP ODO-R 2!                     ( dL dR )
   2OVER 2OVER 2SWAP D- 36 25 R*/ 3600 M/MOD DROP           ( dL dR turn )
   DUP 1800 > IF 3600 - THEN                                 \ -1800 .. 1800
   >R D+ 176 10 R*/                                          ( mils ) ( R: turn )
   POSE-HEADING @ R@ 2/ + 3600 + 3600 MOD                          ( mils mid )
   >R 2DUP R@ COS SCALED POSE-X 2@ D+ POSE-X 2!  R> SIN SCALED POSE-Y 2@ D+ POSE-Y 2!
   POSE-HEADING @ R> + 3600 + 3600 MOD POSE-HEADING ! ;
' ODOMETRY IS MOVED
: .HUNDREDTHS  ( d -- )   TUCK DABS <# # # [CHAR] . HOLD #S ROT SIGN #> TYPE ;
: .POSE  ( -- )   \ x and y in inches, heading in degrees
   ODOMETRY  ." x " POSE-X 2@ 1 10 R*/ .HUNDREDTHS  ."  in  y " POSE-Y 2@ 1 10 R*/ .HUNDREDTHS
   ."  in  heading " POSE-HEADING @ 0 <# # [CHAR] . HOLD #S #> TYPE ."  deg " ;
: .V4  ( d -- )   TUCK DABS <# # # # # [CHAR] . HOLD #S ROT SIGN #> TYPE ;
: .UNIT  ( unit -- )
   CASE 1 OF ." INCHES" ENDOF 2 OF ." FEET" ENDOF 3 OF ." MILES" ENDOF
        4 OF ." DEGREES" ENDOF ENDCASE ;
: .COMMAND  ( cmd# -- )
   CASE 0 OF ." FORWARD" ENDOF 1 OF ." BACKWARD" ENDOF 2 OF ." LEFT" ENDOF
        3 OF ." RIGHT" ENDOF 4 OF ." UP" ENDOF 5 OF ." DOWN" ENDOF
        6 OF ." OPEN" ENDOF 7 OF ." CLOSE" ENDOF ENDCASE ;
: .SETTINGS  ( -- )   \ device, speed, acceleration, each command's last distance
   ." device " DEVICE @ 1 = IF ." RERB" ELSE ." ARM" THEN
   ."   speed " SPEED . ." crpm (8253 count " SPEED >REF 0 U.R ." )  accel "
   ACCEL ? ." crpm/tick  following limit " FERR-LIMIT ? ." counts"
   8 0 DO  CR 2 SPACES I .COMMAND SPACE I LAST-DISTANCE DUP 2@ .V4 SPACE 4 + @ .UNIT  LOOP
   SPACE ;
