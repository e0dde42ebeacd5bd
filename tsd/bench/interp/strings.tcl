# String operations, lappend, array set/get: 200k rounds.
# ops: 200000 rounds
proc main {} {
    set out {}
    for {set i 0} {$i < 200000} {incr i} {
        set k "key[expr {$i % 1000}]"
        set a($k) [string length $k]
        append buf [string index $k end]
        lappend out [string range $k 0 2]
        incr a($k) $a($k)
    }
    return [list [llength $out] [string length $buf] [array size a] $a(key7)]
}
puts [main]
