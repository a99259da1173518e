\ Layer 1, hardware interface: ports, the relay shadow, relay words.
\ Adds port and bit constants, RELAYS ENABLE DISABLE STOP-LEFT STOP-RIGHT
\ STOP FORWARD REVERSE CW CCW GO COAST REF! SENSORS@ BEEP-ON BEEP-OFF.
\ Relies on F83's PC! PC@ (8-bit OUT and IN) and the core words.
\ The board's latches are write-only, so RELAYS keeps a copy of both:
\ low byte the MOTOR latch (0x88), high byte the AUX latch (0x89).
HEX
80 CONSTANT LEFT-8253      84 CONSTANT RIGHT-8253      \ ( -- port )
88 CONSTANT MOTOR-PORT     89 CONSTANT AUX-PORT     8A CONSTANT SENSE-PORT
0001 CONSTANT M1-ON        0002 CONSTANT M1-REV        \ ( -- mask )
0004 CONSTANT M2-ON        0008 CONSTANT M2-REV
0010 CONSTANT M1-GO        0020 CONSTANT M2-GO
0100 CONSTANT ARM-ON       0200 CONSTANT ARM-DOWN
0400 CONSTANT GRIP-ON      0800 CONSTANT GRIP-CLOSE    1000 CONSTANT BEEPER
DECIMAL

VARIABLE RELAYS                  \ ( -- addr ) shadow of both output latches
: LATCH  ( -- )   RELAYS @  DUP 255 AND MOTOR-PORT PC!  8 RSHIFT AUX-PORT PC! ;
: ENABLE  ( mask -- )   RELAYS @ OR RELAYS !  LATCH ;
: DISABLE  ( mask -- )   NOT RELAYS @ AND RELAYS !  LATCH ;

: STOP-LEFT  ( -- )   M1-GO M1-ON OR DISABLE ;      \ relays off: braked
: STOP-RIGHT  ( -- )   M2-GO M2-ON OR DISABLE ;
: STOP  ( -- )   M1-GO M1-ON OR M2-GO OR M2-ON OR DISABLE ;
: FORWARD  ( -- )   M1-REV M2-REV OR DISABLE  M1-ON M2-ON OR ENABLE ;
: REVERSE  ( -- )   M1-REV M2-REV OR M1-ON OR M2-ON OR ENABLE ;
: CW  ( -- )   M1-REV DISABLE  M2-REV M1-ON OR M2-ON OR ENABLE ;   \ turn right
: CCW  ( -- )   M2-REV DISABLE  M1-REV M1-ON OR M2-ON OR ENABLE ;  \ turn left
: GO  ( -- )   M1-GO M2-GO OR ENABLE ;      \ PLLs and drive current on
: COAST  ( -- )   M1-GO M2-GO OR DISABLE ;  \ drive off: the wheels freewheel

\ Counter 0 of each 8253 sets its motor's PLL reference, 125 kHz / u
\ (u = 0 means 65536). INIT-COUNTERS wrote control word 0x36 once.
: REF!  ( u motor# -- )
   1 = IF LEFT-8253 ELSE RIGHT-8253 THEN  >R
   DUP 255 AND R@ PC!  8 RSHIFT R> PC! ;
: SENSORS@  ( -- c )   SENSE-PORT PC@ ;
: BEEP-ON  ( -- )   BEEPER ENABLE ;
: BEEP-OFF  ( -- )   BEEPER DISABLE ;
