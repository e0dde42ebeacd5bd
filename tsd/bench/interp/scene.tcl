# A coordinate-computing scene proc: a 300x300 height field, its vertex
# coordinates and triangle indices computed in Tcl (what a .tsd generator
# does before calling vertex and tri).
# ops: 90000 cells
proc height {x z} { expr {0.3 * sin(3.0 * $x) * cos(2.0 * $z) + 0.05 * $x * $z} }
proc field {n} {
    set verts {}
    set tris {}
    for {set i 0} {$i <= $n} {incr i} {
        set x [expr {double($i) / $n * 2.0 - 1.0}]
        for {set j 0} {$j <= $n} {incr j} {
            set z [expr {double($j) / $n * 2.0 - 1.0}]
            lappend verts $x [height $x $z] $z
        }
    }
    set w [expr {$n + 1}]
    for {set i 0} {$i < $n} {incr i} {
        for {set j 0} {$j < $n} {incr j} {
            set a [expr {$i * $w + $j}]
            lappend tris $a [expr {$a + 1}] [expr {$a + $w}]
            lappend tris [expr {$a + 1}] [expr {$a + $w + 1}] [expr {$a + $w}]
        }
    }
    return [list [llength $verts] [llength $tris] [format %.6f [lindex $verts 1000]]]
}
puts [field 300]
