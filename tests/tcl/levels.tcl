# Levels, links and namespace variables as Tcl reads them (issue "Tcl 8.6").
proc lev {args} { list [catch {uplevel {*}$args} m] $m }
puts [apply {{} {lev -0 {}}}]
puts [apply {{} {lev #-0 {}}}]
puts [apply {{} {lev 0x0 {set x 1}}}]
puts [lev 1]
puts [lev 1a {}]
puts [lev #x {}]
puts [catch {upvar 1 x} m]$m
# A link may be moved; a variable may not be replaced by one.
proc p1 {} { set a(0) zeroth; set a(1) first; p2 }
proc p2 {} {
    upvar a x
    set r {}
    foreach i [lsort [array names x]] { upvar a($i) x; lappend r $x }
    set r
}
puts [p1]
proc p3 {} { set y 1; upvar #0 z y }
puts [list [catch p3 m] $m]
# `variable` names the namespace's variable, even with a global of that name.
set v global
namespace eval ns1 { variable v 123; proc p {} { variable v; return $v } }
puts [list [ns1::p] $v]
set w 1
namespace eval ns2 { set w 5 }
puts $w
puts [variable]
puts [list [catch {namespace eval nope {}; namespace delete nope; namespace children nope} m] $m]
puts [list [catch {namespace delete ::nowhere} m] $m]
puts [list [catch {array set arr(x) {a 1}} m] $m]
