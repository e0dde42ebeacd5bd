# while with incr: 2M iterations.
# ops: 2000000 iterations
proc main {} {
    set i 0
    set n 0
    while {$i < 2000000} {
        incr i
        incr n 2
    }
    return $n
}
puts [main]
