proc sieve n {
    set primes {}
    for {set i 2} {$i <= $n} {incr i} { set is($i) 1 }
    for {set i 2} {$i * $i <= $n} {incr i} {
        if {$is($i)} { for {set j [expr {$i*$i}]} {$j <= $n} {incr j $i} { set is($j) 0 } }
    }
    for {set i 2} {$i <= $n} {incr i} { if {$is($i)} { lappend primes $i } }
    return $primes
}
puts [sieve 200]
puts [llength [sieve 10000]]
