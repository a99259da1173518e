\ Listing 6: MAILBOT, eight trips a day on the half hour.
\ As printed:
\     MAILBOT (---)
\     8.5 AM WAIT-UNTIL TRIP
\     9.5 AM WAIT-UNTIL TRIP
\     10.5 AM WAIT-UNTIL TRIP
\     11.5 AM WAIT-UNTIL TRIP
\     1.5 PM WAIT-UNTIL TRIP
\     2.5 PM WAIT-UNTIL TRIP
\     3.5 PM WAIT-UNTIL TRIP
\     4.5 PM WAIT-UNTIL TRIP
\ Repaired: the leading ":" and the closing ";" were lost, "(---)" needs
\ its blanks. 8.5 AM is 8:30 (hours, minutes as fractions), 3,060,000
\ ticks; WAIT-UNTIL waits until the time of day is exactly that. The
\ numbers are compiled, so this needs RCL literals (on by default).
\ Start it in the morning, e.g.   8 AM TICKS!  MAILBOT
REQUIRE listing5.fs
: MAILBOT  ( -- )
    8.5 AM WAIT-UNTIL TRIP    9.5 AM WAIT-UNTIL TRIP
   10.5 AM WAIT-UNTIL TRIP   11.5 AM WAIT-UNTIL TRIP
    1.5 PM WAIT-UNTIL TRIP    2.5 PM WAIT-UNTIL TRIP
    3.5 PM WAIT-UNTIL TRIP    4.5 PM WAIT-UNTIL TRIP ;
