set a 1; puts [set a]; puts [set b 2]
append s hello " " world; puts $s
incr n; incr n 5; incr n -2; puts $n
puts [catch {incr s} m]$m
unset a; puts [info exists a]; puts [catch {unset a} m]$m; unset -nocomplain a
array set colors {red 1 green 2 blue 3}
puts [array size colors][array exists colors][array exists nope][lsort [array names colors]]
puts [lsort [array names colors g*]]; puts [llength [array get colors]]
set colors(white) 4; puts $colors(white); unset colors(red); puts [lsort [array names colors]]
puts [catch {set colors} m]$m; puts [catch {set colors(nope)} m]$m; puts [catch {set a(1) x; set a} m]$m
array unset colors; puts [array exists colors]
set x 5; puts [catch {set x(1) 2} m]$m
set ::gv global; puts $gv; puts $::gv
set i 0; set v$i zero; puts $v0
set lst {}; foreach w {a b c} { lappend lst [string toupper $w] }; puts $lst
set str ""; for {set i 0} {$i < 5} {incr i} { append str $i }; puts $str
