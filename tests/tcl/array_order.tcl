# array names/get in Tcl hash order (and -exact/-glob/-regexp).
for {set i 0} {$i < 60} {incr i} { set a(k$i) $i }
puts [array names a]
array set b {apple 1 banana 2 cherry 3 date 4 elder 5 fig 6 grape 7 x 8 y 9 z 10 aa 11 bb 12 cc 13 1 1 2 2 10 10 100 100}
puts [array names b]
puts [array get b]
puts [array names b -glob *a*]
puts [array names b -exact fig]
puts [array names b -regexp {^[a-c]}]
foreach w {the quick brown fox jumps over the lazy dog and then some more words to fill a table past its rebuild sizes of twelve and forty eight} { incr c($w) }
puts [array get c]
set m(0,0) 1; set m(0,1) 2; set m(1,0) 3; set m(1,1) 4; puts [array names m]
