# errorInfo as Tcl 8.6 builds it: one line per evaluation unit, body
# frames for foreach/lmap/switch/dict for outside procs, eval, uplevel.
proc f {} {
  set a 1
  set x [string index]
}
catch f; puts $::errorInfo; puts ---
proc g {} {
  if {1} {
     set y 2
     error boom
  }
}
catch g; puts $::errorInfo; puts ---
catch {error msg1 msg2 msg3}; puts $::errorInfo; puts ---
catch {set z [error msg1 msg2 msg3]}; puts $::errorInfo; puts ---
catch {format [string index]}; puts $::errorInfo; puts ---
catch {foreach i {1 2} { if {$i == 2} { list [lindex] } }}; puts $::errorInfo; puts ---
proc k {} { uplevel 1 {error up} }
catch k; puts $::errorInfo; puts ---
proc m {} { foreach i {1 2} {
  dict for {a b} {x y} {
     error inner
  }
}}
catch m; puts $::errorInfo; puts ---
proc n {} { return -code error -errorinfo custom oops }
catch {set r [n]}; puts $::errorInfo; puts ---
catch {apply {{} {
  set x 1
  error lam
}}}; puts $::errorInfo; puts ---
catch {namespace eval zz {
  error nse
}}; puts $::errorInfo; puts ---
catch {try { error t1 } finally { set w 1 }}; puts $::errorInfo; puts ---
catch {while 1 {
  error wl
}}; puts $::errorInfo; puts ---
proc p {} { catch {foreach i {1 2} { if {$i == 2} { list [lindex] } }}; return $::errorInfo }
puts [p]; puts ---
catch {foreach i {1 2} { if {$i == 2} { list [lindex] } }}; puts $::errorInfo; puts ---
foreach i {1 2} { catch { if {$i == 2} { list [lindex] } } }; puts $::errorInfo; puts ---
catch {if 1 { list [lindex] } }; puts $::errorInfo; puts ---
catch {while 1 { list [lindex] } }; puts $::errorInfo; puts ---
catch {for {} 1 {} { list [lindex] } }; puts $::errorInfo; puts ---
catch {switch a a { list [lindex] } }; puts $::errorInfo; puts ---
catch {dict for {a b} {x y} { list [lindex] } }; puts $::errorInfo; puts ---
catch {lmap a {x y} { list [lindex] } }; puts $::errorInfo; puts ---
catch {foreach a {x y} { list [lindex] } }; puts $::errorInfo; puts ---
catch {foreach a {x y} { 
  set x 1
  list [lindex] } }; puts $::errorInfo; puts ---
catch {try {error a} on error {} {
  error b}}; puts $::errorInfo; puts ---
proc p {} {try {error a} on error {} {
  error b}}
catch p; puts $::errorInfo; puts ---
catch {try {set x 1} finally {
  error c}}; puts $::errorInfo; puts ---
catch {switch b a - b {
 error sw}}; puts $::errorInfo; puts ---
catch {eval {set x 1
 error ev}}; puts $::errorInfo; puts ---
catch {eval set x \[error ev2\]}; puts $::errorInfo; puts ---
