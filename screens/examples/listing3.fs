\ Listing 3: the delays, exactly as the article defines them.
\ As printed:
\     : MS (milliseconds ----)
\     0 ?DO 33 0 DO LOOP LOOP;
\     : SECONDS (seconds ---) 0 ?DO 1000 MS LOOP;
\     : MINUTES (minutes ---)
\     0 ?DO 60 SECONDS LOOP;
\ Repaired: blanks after "(" and before ";". MS is a calibrated empty loop:
\ 33 turns of the inner loop a millisecond on the 80188. RCL's own MS
\ (layer 9) spends exactly this loop's virtual time without running it;
\ loading this file replaces it with the loop itself (slower to simulate,
\ the same virtual time).
: MS  ( milliseconds -- )   0 ?DO 33 0 DO LOOP LOOP ;
: SECONDS  ( seconds -- )   0 ?DO 1000 MS LOOP ;
: MINUTES  ( minutes -- )   0 ?DO 60 SECONDS LOOP ;
