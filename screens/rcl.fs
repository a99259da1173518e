\ RCL, the Robotic Control Language: the load screen. Loads the layers in
\ the article's order and starts the 10 ms control loop, so the robot is
\ ready at the prompt. F83's own BEEP MS GO UP OPEN STOP FORWARD CONTROL
\ are shadowed on purpose; WARNING is off so they load quietly.
WARNING OFF
INCLUDE 10-hardware.fs
INCLUDE 20-interrupts.fs
INCLUDE 30-counters.fs
INCLUDE 40-following.fs
INCLUDE 50-fixed.fs
INCLUDE 60-units.fs
INCLUDE 70-motion.fs
INCLUDE 75-control.fs
INCLUDE 80-commands.fs
INCLUDE 90-time.fs
INCLUDE 95-status.fs
' (SAFE) SAFE-STATE !   \ run after every error, before the user's ON-ABORT
WARNING ON
DECIMAL INSTALL
HERE FENCE !     \ EMPTY forgets the user's words only; FORGET stops here
HALT             \ start just after a tick: what the user runs next does not
                 \ depend on how long these screens took to load
