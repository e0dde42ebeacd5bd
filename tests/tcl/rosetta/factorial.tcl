package require Tcl 8.5
proc fact n { expr {$n < 2 ? 1 : $n * [fact [expr {$n - 1}]]} }
proc ifact n { set r 1; for {set i 2} {$i <= $n} {incr i} { set r [expr {$r * $i}] }; return $r }
foreach n {0 1 5 10 20 25 50 100} { puts "$n! = [fact $n]" }
puts [expr {[fact 30] == [ifact 30]}]
puts [string length [ifact 500]]
