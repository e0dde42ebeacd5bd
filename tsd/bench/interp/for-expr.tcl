# Nested for loops with expr: 1M inner iterations.
# ops: 1000000 iterations
proc main {} {
    set s 0.0
    for {set i 0} {$i < 1000} {incr i} {
        for {set j 0} {$j < 1000} {incr j} {
            set s [expr {$s + $i * 0.5 - $j * 0.25}]
        }
    }
    return $s
}
puts [main]
