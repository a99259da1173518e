\ Listing 1: the square (Radio-Electronics, the robot's command language).
\ As printed:
\     .1G (3.22 ft/sec/sec)
\     RERB 25.5 IPS
\     3.5 FEET FORWARD 90 DEGREES LEFT
\ Repaired: ".1G" is `.1 G` (the blank was lost in print) and the comment
\ needs a blank after its "(". The prose says the last line is done four
\ times in all ("repeated three times"); by the optional-parameter rule
\ the repeats can be written FORWARD LEFT. Expected: ACCEL 132, 8253 count
\ 173, 1193 counts a side, 313 a turn; back within an inch of the start.
.1 G  ( 3.22 ft/sec/sec )
RERB 25.5 IPS
3.5 FEET FORWARD 90 DEGREES LEFT
FORWARD LEFT
FORWARD LEFT
FORWARD LEFT
