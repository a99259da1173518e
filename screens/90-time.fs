\ Layer 9, time: delays, the time of day, the beeper.
\ Adds MS SECONDS MINUTES BEEP AM PM IDLE? ?TIME WAIT-UNTIL .TIME SET-CLOCK.
\ Relies on TICKS@ (layer 2), the relay words and STALL? (layer 8). MS is
\ Listing 3's calibrated loop `0 ?DO 33 0 DO LOOP LOOP`; here a CODE word
\ spends exactly that loop's virtual time, with every tick still serviced;
\ like every wait it refuses to start when no tick can come.
: IDLE?  ( -- f )   \ every tick's handler would only read: a wait may skip
   MOVING @ ARM-BITS @ OR 0=  STOCK? AND ;
CODE IDLE-CELLS  ( -- addr )  where (MS) finds IDLE?, which it asks outside
   time (MS keeps its calibrated time); then the cells IDLE? reads, which keep
   this table and the load of the screens as long as they were
END-CODE  ' IDLE? ,  MOVING ,  ARM-BITS ,  STOCK-CONTROL ,
CODE (MS)  ( n -- )  spend 4 + 37n primitives of foreground time (after
   ?TICKING's check, at no cost); while IDLE? it counts idle ticks out.
END-CODE
: MS  ( milliseconds -- )   (MS) ;   \ wait, Listing 3's calibrated loop
: SECONDS  ( seconds -- )   ?DURATION 0 ?DO 1000 MS LOOP ;   \ wait n times 1000 MS
: MINUTES  ( minutes -- )   ?DURATION 0 ?DO 60 SECONDS LOOP ;   \ wait n times 60 SECONDS
: BEEP  ( -- )   BEEP-ON 100 MS BEEP-OFF 100 MS ;   \ two BEEPs are two sounds

\ The time of day is counted in 10 ms ticks since midnight once INSTALL
\ has run: 1/10000 hour = 0.36 s = 36 ticks.
: HOURS  ( frac int -- d )
   DUP 0 13 WITHIN 0= ABORT" Bad time"  OVER 0< ABORT" Bad time"
   >V4 36 1 M*/ ;
: AM  ( num -- d )   FIXED  DUP 12 = IF DROP 0 THEN  HOURS ;   \ 12 AM is midnight
: PM  ( num -- d )   FIXED  DUP 12 = >R HOURS R> 0= IF 4320000. D+ THEN ;   \ afternoon hours to ticks: 1.5 PM

CODE (SKIP-TO-TICK)  ( d -- )  let the clock run to that tick at once.
END-CODE
: ?TIME  ( d -- )   \ a time of day that comes: 0 to the ticks of a day
   2DUP D0< >R  PER-DAY@ D< 0= R> OR ABORT" Bad time" ;
: WAIT-UNTIL  ( d -- )   \ until the time of day is exactly d (maybe tomorrow)
   2DUP ?TIME  ?TICKING  IDLE? IF 2DUP (SKIP-TO-TICK) THEN
   0 BEGIN  >R 2DUP TICKS@ D= 0= WHILE
      TICKS@ DROP HALT TICKS@ DROP R> STALL?
   REPEAT  R> DROP 2DROP ;
: .00  ( n -- )   0 <# # # #> TYPE ;
: .TIME  ( -- )   \ hh:mm:ss
   TICKS@ 100 MU/MOD ROT DROP  60 MU/MOD ROT >R  60 MU/MOD ROT >R  DROP
   .00 [CHAR] : EMIT  R> .00 [CHAR] : EMIT  R> .00 SPACE ;
: SET-CLOCK  ( hh mm -- )   \ set the time of day, 24-hour: 13 30 SET-CLOCK
   DUP 0 60 WITHIN 0= ABORT" Bad time"  OVER 0 24 WITHIN 0= ABORT" Bad time"
   SWAP 60 * +  6000 UM* TICKS! ;
