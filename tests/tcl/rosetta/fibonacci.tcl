proc fib n {
    lassign {0 1} a b
    for {set i 0} {$i < $n} {incr i} { lassign [list $b [expr {$a + $b}]] a b }
    return $a
}
proc fibr n { if {$n < 2} {return $n}; expr {[fibr [expr {$n-1}]] + [fibr [expr {$n-2}]]} }
puts [lmap n {0 1 2 3 10 20 50 90 93 100 200} { fib $n }]
puts [fibr 20]
