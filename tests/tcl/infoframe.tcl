# info frame (issue "Tcl 8.6"): the units in progress and where their
# commands are, in the main script, in procs, in sourced files, under
# eval/uplevel/catch/if with literal and dynamic scripts, lambdas,
# coroutines and backslash-newlines in braced bodies.
proc show {{n -1}} {
    set f [info frame $n]
    if {[dict exists $f file]} { dict set f file [file tail [dict get $f file]] }
    puts $f
}
proc depth {} { puts "depth [info frame]" }
proc types {} {
    set r {}
    for {set i [info frame]} {$i > 0} {incr i -1} { lappend r [dict get [info frame $i] type] }
    puts "[info frame] $r"
}
show 0
eval {
  show
}
set s {
  show
}
eval $s
proc p {} {
  eval {
    show
  }
  show
  set res \
    [show]
  set r2 [list a \
     [show]]
  puts [subst {[show]}]
  set body {
   show
  }
  if 1 $body
  catch {show}
  foreach x 1 { show }
  eval { foreach x 1 { depth } }
  uplevel 0 { foreach x 1 { depth } }
}
p
set body {
  eval {
    show
  }
  show
}
proc q {} $body
q
if 1 {
  show
}
depth
proc w {x} { uplevel 1 $x }
w {
  show
}
set t {show}
w $t
catch {show}
puts "[show]"
apply {{} {
 show
}}
namespace eval zz {
  show
}
namespace eval zz { proc s2 {} { show } }
zz::s2
foreach x {1} { show }
set b {
  proc inner {} {
     show
  }
  eval {
    eval {
      show
    }
  }
}
proc outer {} $b
outer
inner
coroutine co apply {{} { show; yield; show }}
co
puts [expr {[info frame]}]
if {[catch {info frame} x] == 0} { puts "if-catch $x" }
types
if {[catch {types}]} {}
# A sourced file runs as one compiled unit: if/catch/while add no unit,
# foreach and switch at its top level do.
set dir /tmp/rayshell-infoframe-[pid]
file mkdir $dir
set fd [open $dir/sourced.tcl w]
puts $fd {show 0
if 1 { depth }
catch { depth }
while 1 { depth; break }
foreach x 1 { depth }
switch a a { depth }
proc t1 {body} { uplevel 1 $body }
t1 {
  show
}
proc in_file {} {
  show 0
}
in_file
types}
close $fd
source $dir/sourced.tcl
proc src {} { source $::dir/sourced.tcl }
src
proc t2 {body} { uplevel 1 $body }
t2 {
  show
}
catch {info frame 99} m; puts $m
catch {info frame -99} m; puts $m
catch {info frame x} m; puts $m
catch {info frame 1 2} m; puts $m
file delete -force $dir
