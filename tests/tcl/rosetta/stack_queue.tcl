namespace eval stack {
    variable items {}
    proc push x { variable items; lappend items $x; return }
    proc pop {} { variable items; set x [lindex $items end]; set items [lrange $items 0 end-1]; return $x }
    proc empty {} { variable items; expr {[llength $items] == 0} }
    namespace export *
    namespace ensemble create
}
foreach x {a b c d} { stack push $x }
while {![stack empty]} { puts -nonewline "[stack pop] " }
puts ""
set q [list]
foreach x {1 2 3} { lappend q $x }
while {[llength $q]} { set q [lassign $q head]; puts -nonewline "$head " }
puts ""
