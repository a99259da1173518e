\ The arm routine of the article: the arm down 3.1 inches, then up 2.
\ As printed:   ARM 3.1 INCHES DOWN 2 INCHES UP
\ Nothing to repair. The lift starts at the top (8.0 in): it ends at 6.9
\ (310 ticks down at 1 in/s, then 200 up).
ARM 3.1 INCHES DOWN 2 INCHES UP
