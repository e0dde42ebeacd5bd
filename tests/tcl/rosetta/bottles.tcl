package require Tcl 8.5
proc bottles n {
    switch $n {
        0 {return "No more bottles"}
        1 {return "1 bottle"}
        default {return "$n bottles"}
    }
}
for {set i 99} {$i > 0} {incr i -1} {
    puts "[bottles $i] of beer on the wall, [string tolower [bottles $i]] of beer."
    puts "Take one down and pass it around, [string tolower [bottles [expr {$i-1}]]] of beer on the wall.\n"
}
