# namespace (issue "Tcl 8.6"): eval, procs and variables in namespaces, import,
# ensembles, code, delete, which, qualifiers, against tclsh.
namespace eval geo {
    variable count 0
    proc area {w h} { variable count; incr count; return [expr {$w * $h}] }
    proc twice {w h} { expr {2 * [area $w $h]} }
    namespace export area
}
puts [geo::area 2 3]
puts [geo::twice 2 3]
puts $geo::count
puts [namespace current]
puts [namespace eval geo {namespace current}]
puts [namespace exists geo] 
puts [namespace exists nope]
puts [lsort [namespace children :: g*]]
puts [namespace qualifiers ::a::b::c]; puts [namespace tail ::a::b::c]
puts [namespace which -command geo::area]
puts [namespace which -command puts]
namespace import geo::area
puts [area 4 5]
namespace eval geo::inner { proc hi {} { return [namespace current] } }
puts [geo::inner::hi]
puts [namespace parent geo::inner]
puts [namespace children geo]
namespace eval cfg {
    variable width 640
    proc get {k} { variable $k; return [set $k] }
    namespace export get put
    namespace ensemble create
}
puts [cfg get width]
catch {cfg nosuch} e; puts $e
set cb [namespace eval geo {namespace code {area 7 7}}]
puts $cb
puts [eval $cb]
namespace delete geo
puts [namespace exists geo]
catch {geo::area 1 1} e; puts $e
set x global
namespace eval q { puts $x; set y 1 }
puts [info exists q::y]
catch {namespace eval} e; puts $e
catch {namespace foo} e; puts $e
proc ::cfg::put {k v} { variable $k $v }
cfg put height 480
puts $cfg::height
