\ Listing 2: BOX, a square of any size.
\ As printed:
\     : BOX (feet ---)
\     RERB
\     25.5 IPS
\     2DUP (FEET) FORWARD
\     90 DEGREES RIGHT
\     2DUP (FEET) FORWARD
\     90 DEGREES RIGHT;
\ Repaired (the printed text is above): the stack comment needs its blank; ";" was
\ fused to RIGHT; only two sides were printed. (FEET) takes a FIXED pair,
\ so 2DUP keeps it for the next side and the last side consumes it.
\ Use:   3.5 FIXED BOX      (the argument is a FIXED pair: frac int)
: BOX  ( frac int -- )   \ a square with sides of that many feet
   RERB
   25.5 IPS
   2DUP (FEET) FORWARD  90 DEGREES RIGHT
   2DUP (FEET) FORWARD  90 DEGREES RIGHT
   2DUP (FEET) FORWARD  90 DEGREES RIGHT
        (FEET) FORWARD  90 DEGREES RIGHT ;
