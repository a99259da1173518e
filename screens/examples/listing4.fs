\ Listing 4: words for convenience and readability (the mail robot).
\ As printed:
\     ATTENTION ( --- )
\     BEEP BEEP 1 SECONDS ;
\     : WARNING ( ---- ) 5 0 DO BEEP 1 SECONDS LOOP ;
\     : TURN-AROUND ( ---- )
\     RERB 10 IPS 180 DEGREES
\     LEFT :
\     : TURN-LEFT ( ---- ) 90 DEGREES LEFT ;
\     : TURN-RIGHT ( ---- ) 90 DEGREES RIGHT ;
\     : AHEAD ( feet ----) FEET FORWARD ;
\     COLLECT ( minutes ---- )
\     ATTENTION MINUTES WARNING ;
\ Repaired (the printed text is above): ATTENTION and COLLECT lost their leading ":",
\ TURN-AROUND ends with ":" for ";", and "(feet ----)" needs its blank.
\ BEEP (layer 9) is used but never defined in the article. WARNING
\ shadows F83's WARNING variable: from here on the name is the beeper.
\ TURN-AROUND leaves the speed at 10 IPS (the optional-parameter rule).
: ATTENTION  ( -- )   BEEP BEEP 1 SECONDS ;
: WARNING  ( -- )   5 0 DO BEEP 1 SECONDS LOOP ;
: TURN-AROUND  ( -- )   RERB 10 IPS 180 DEGREES LEFT ;
: TURN-LEFT  ( -- )   90 DEGREES LEFT ;
: TURN-RIGHT  ( -- )   90 DEGREES RIGHT ;
: AHEAD  ( feet -- )   FEET FORWARD ;
: COLLECT  ( minutes -- )   ATTENTION MINUTES WARNING ;
