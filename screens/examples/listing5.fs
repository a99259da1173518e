\ Listing 5: TRIP, one mail round of the model office (Fig. 2).
\ As printed (the text came out of the magazine in four columns, read one
\ after the other):
\   :TRIP () WARNING BACKWARD TURN-RIGHT 5 AHEAD 10 AHEAD 7 AHEAD
\   TURN-RIGHT 3 AHEAD 4 COLLECT ATTENTION 14 AHEAD TURN-RIGHT 10 IPS
\   | RERB TURN-AROUND 12 AHEAD TURN-LEFT TURN-RIGHT 2 COLLECT 25 AHEAD
\   2 COLLECT 11.5 AHEAD 3 COLLECT TURN-LEFT 12 AHEAD 5.5 AHEAD
\   | 20 IPS 2.5 AHEAD TURN-LEFT 36 IPS 2 COLLECT 8 AHEAD TURN-RIGHT
\   11.5 AHEAD TURN-RIGHT ( President) 4.5 AHEAD TURN-LEFT
\   | 3 FEET
\ Reconstructed (about 75 % sure of the order): read row
\ by row, the header alone on the first row, columns 2 to 4 from the
\ second. Only that reading backs out of the nest first and never repeats
\ an action twice running; the turns net +180 degrees, cancelling
\ TURN-AROUND. Also repaired: ":TRIP" and "()" need blanks, ";" was lost.
\ Collects 2, 2, 2, 4 and 3 minutes; about 15 minutes a trip.
REQUIRE listing4.fs
: TRIP  ( -- )
   WARNING      RERB          20 IPS       3 FEET
   BACKWARD     TURN-AROUND   2.5 AHEAD
   TURN-RIGHT   12 AHEAD      TURN-LEFT
   5 AHEAD      TURN-LEFT     36 IPS
   10 AHEAD     TURN-RIGHT    2 COLLECT
   7 AHEAD      2 COLLECT     8 AHEAD
   TURN-RIGHT   25 AHEAD      TURN-RIGHT
   3 AHEAD      2 COLLECT     11.5 AHEAD
   4 COLLECT    11.5 AHEAD    TURN-RIGHT
   ATTENTION    3 COLLECT     ( President )
   14 AHEAD     TURN-LEFT     4.5 AHEAD
   TURN-RIGHT   12 AHEAD      TURN-LEFT
   10 IPS       5.5 AHEAD   ;
