\ docs/guide.md section 3: a compiled number restores its compile-time DPL.
: S  5 ;  : D  11.5 ;  : DD  1.25 ;
S DPL @ . DROP
D DPL @ . D.
DD DPL @ . D.
8.5 DPL @ . 2DROP
S DPL @ . .
SEE D
