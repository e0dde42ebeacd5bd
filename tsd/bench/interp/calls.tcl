# 1M calls of a 3-argument proc.
# ops: 1000000 calls
proc add3 {a b c} { expr {$a + $b + $c} }
proc main {} {
    set s 0
    for {set i 0} {$i < 1000000} {incr i} {
        set s [add3 $s $i 1]
    }
    return $s
}
puts [main]
