\ Kernel: the ROOT vocabulary also knows FORTH and WORDS, so that
\ ONLY FORTH ALSO DEFINITIONS works from any search order (F83).
ALSO ROOT DEFINITIONS
: FORTH  ( -- )  FORTH ;
: WORDS  ( -- )  WORDS ;
PREVIOUS DEFINITIONS
