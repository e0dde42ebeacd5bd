# Tcl 8.6 features added for issue "Tcl 8.6": apply, lmap, subst, try/throw,
# return -options, codes beyond 4, interp alias, variable, package, string last.
catch {apply {{x y} {return [expr {$x+$y}]}} 1} e; puts $e
catch {apply {{x y} {error boom}} 1 2} e o; puts $::errorInfo
catch {apply {x y z w}} e; puts $e
catch {apply {{x {y 2}} {list $x $y}} 1 2 3} e; puts $e
puts [apply {args {llength $args}} 1 2 3]
catch {apply} e; puts $e
puts [lmap x {1 2 3 4} {if {$x == 2} continue; if {$x == 4} break; expr {$x*10}}]
puts [lmap {a b} {1 2 3 4 5} {list $b $a}]
catch {lmap x} e; puts $e
puts [apply {{x} {apply {{y} {expr {$y*2}}} $x}} 21]
set a 5; set arr(x) 7
puts [subst {a=$a b=$arr(x) [expr {1+2}] \t"q" {br}}]
puts [subst -nocommands {a=$a [expr {1+2}] \n}]
puts [subst -novariables {a=$a [expr {1+2}]}]
puts [subst -nobackslashes {a=$a \n}]
puts [subst {x[break]y}]
puts [subst {x[continue]y}]
puts [subst {x[return foo]y}]
catch {subst {x[error bad]y}} e; puts $e
catch {subst {x[}} e; puts $e
catch {subst -nofoo x} e; puts $e
catch {subst} e; puts $e
puts [subst {$}]
puts [subst {a\
b}]
catch {proc p {a(1)} {}} e; puts $e
catch {proc p {a::b} {}} e; puts $e
catch {apply {a(1) boo}} e o; puts $::errorInfo
catch {apply {{{}} boo}} e o; puts $::errorInfo
puts [apply {{} {info level 0}}]
puts [apply {args {info level 0}} x y]
catch {apply {{x y} {error boom}} 1 2} e o; puts $::errorInfo
catch {apply {{x {y 2}} {list $x $y}} 1 2 3} e; puts $e
puts [apply {{a {b 3} args} {list $a $b $args}} 1]
catch {return -code 5 foo} r o; puts "$r | $o"
proc p {} {return -code 5 x}; puts [catch p r o]; puts "$r $o"
puts [try {throw {A B} msg} trap {A} {m o} {list trapped $m}]
puts [try {expr 1} on ok {r} {list ok $r} finally {puts fin}]
puts [catch {try {error a} finally {error b}} m]; puts $m
puts [catch {try {error a} on error {} {error c}} m o]; puts $m
puts [try {error x} on break {} {list b} on error {} - on continue {} {list e-or-c}]
catch {throw {} msg} e; puts $e
catch {throw} e; puts $e
catch {try {}  on foo {} {}} e; puts $e
catch {try {} on error} e; puts $e
set o [list -code 1 -errorcode {X Y}]
puts [catch {return -options $o hello} r oo]; puts "$r | $oo"
proc q {} { try { return 5 } finally { set ::f 1 } }; puts [q]
proc t {} { foreach i {1 2 3} { try { if {$i == 2} continue; lappend r $i } finally {} }; return $r }; puts [t]
puts [catch {try {error e1 "" {E1 X}} trap {E2} {} {puts no} trap {E1} {m} {set m}} r]; puts $r
interp alias {} say {} puts -nonewline
say hello; puts ""
puts [interp alias {} say]
interp alias {} add {} expr 1 +
puts [add 5]
puts [interp aliases]
interp alias {} add {}
puts [info commands add]
puts [interp recursionlimit {}]
interp recursionlimit {} 500
puts [interp recursionlimit {}]
puts [interp eval {} {set q 3}]
variable zz 5
proc v {} { variable zz; incr zz }
puts [v]
puts $zz
catch {interp alias} e; puts $e
foreach t {{ba badbad end-2} {ba badbad} {ba badbad 4} {ba badbad 1} {ba badbad 0} {a abc 100} {x abc -5}} {
    puts [string last {*}$t]
}
puts [package require Tcl 8.5]
puts [package vsatisfies [info patchlevel] 8.5-]
puts [list $tcl_version [info tclversion] $tcl_platform(platform) [package vcompare 8.6 8.10]]
package provide mypkg 1.2
puts [package present mypkg]
package ifneeded other 2.0 {package provide other 2.0}
puts [package require other]
catch {package require nosuchpkg} e; puts $e
catch {package require Tcl 9} e; puts $e
puts [::list a b]
puts [info commands ::lmap]
# string is -failindex and -strict
foreach {c s} [list integer 12a3 double 1.5x alpha ab1 boolean xyz integer "" digit 12 integer " 12 " double 1e5q] {
  set r [string is $c -failindex f $s]; puts "$c '$s' $r [expr {[info exists f] ? $f : "-"}]"; unset -nocomplain f
}
catch {string is integer -foo x} e; puts $e
puts [string is integer -strict -failindex g ""]; puts $g
