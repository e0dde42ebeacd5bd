package require Tcl 8.5
for {set i 1} {$i <= 100} {incr i} {
    set out ""
    if {$i % 3 == 0} {append out Fizz}
    if {$i % 5 == 0} {append out Buzz}
    puts [expr {$out eq "" ? $i : $out}]
}
