# foreach over a 1M-element list.
# ops: 1000000 elements
proc main {} {
    set l {}
    for {set i 0} {$i < 1000000} {incr i} { lappend l $i }
    set s 0
    foreach x $l { incr s $x }
    return $s
}
puts [main]
