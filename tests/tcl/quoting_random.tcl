# Random strings of special characters, quoted as list elements and parsed
# back: tclsh and raytrace share rand() after srand, so they see the same
# strings; the printed lists must agree byte for byte.
expr {srand(2024)}
set chars [list a b " " "\{" "\}" "\[" "\]" "\$" "\\" "\"" ";" "#" "\n" "\t" x 0 9]
set n [llength $chars]
for {set i 0} {$i < 400} {incr i} {
    set s ""
    set len [expr {int(rand() * 6)}]
    for {set j 0} {$j < $len} {incr j} {
        append s [lindex $chars [expr {int(rand() * $n)}]]
    }
    set l [list $s "#$s" $s]
    puts $l
    if {[lindex $l 0] ne $s || [llength $l] != 3} { puts "round trip failed for [list $s]" }
}
puts [expr {rand()}]
