# Bugs issue "Tcl 8.6" listed, each checked against tclsh: recursion depth,
# string last, unset through upvar, upvar to elements, return codes,
# errorCode of built-in errors, isqrt, format flags, if/switch/proc shape.
proc d n {if {$n} {return [d [expr {$n-1}]]}}; puts [catch {d 400} m]$m
puts [string last ba badbad end-2]
proc u {} { upvar x y; unset y; set y 5 }; set x 1; u; puts $x
proc ua {} { upvar a(1) e; set e 7 }; catch {ua} m; puts [array get a]$m
puts [catch {return -code 5} m]$m
proc ro {} { return -options {-code break} x }; puts [catch ro m]$m
catch {set nosuch} m; puts $::errorCode
puts [expr {isqrt((1<<56)+(1<<29))}]
puts [format {%#.0e|%#x|%05s|%hd} 5 0 ab 70000]
puts [string is integer 9223372036854775807]
puts [string is wideinteger 9223372036854775808]
puts [catch {expr {0.0**-1}} m]$m
puts [catch {expr NaN} m]$m
set i 0; for {} {$i < 3} {incr i; break} { puts i=$i }
puts [catch {if 1 {} elwood {}} m]$m
puts [catch {switch -exact -exact a a {}} m]$m
puts [catch {proc p {a(1)} {}} m]$m
proc uv {} { upvar x x }; puts [catch uv m]$m
proc uv2 {} { set x 1; upvar 0 x x }; puts [catch uv2 m]$m
proc il {} { global x; set y 1; info locals }; puts [il]
proc t {} { upvar a(1) e; set e 7; append e x; incr ::n; info exists e }
set n 0; puts [t]; puts [array get a]
proc t2 {} { upvar a(2) e; info exists e }
puts [t2]
proc t3 {} { upvar a(1) e; unset e; info exists e }
puts [t3]; puts [array get a]
proc t4 {} { upvar a(1) e; set e(x) 1 }
puts [catch t4 m]$m
set s 5
proc t5 {} { upvar s(1) e; set e 1 }
puts [catch t5 m]$m
proc t6 {} { upvar a(3) e; lappend e p q; set e }
puts [t6]
set cases {
  {set}
  {nosuchcmd}
  {set a(1) 1; set a}
  {expr 1/0}
  {expr 1%0}
  {expr {"a"+1}}
  {lindex {a b} x}
  {string repeat}
  {list "a"b}
  {expr sqrt(-1)}
  {error foo}
  {throw {A B} msg}
  {dict get {a 1} b}
  {lrange}
  {format %d x}
  {proc}
  {namespace eval}
  {set nv}
  {unset nv}
  {llength "a \{"}
}
foreach c $cases {
  catch {uplevel #0 $c} m o; puts "[list $c] -> [dict get $o -errorcode]"
}
foreach f {%#.0e %#.0f %#g %#.3g %#x %#o %#b %#X %05s %-05s %05c %#.0E %+05d %05x % d %+s} {
  foreach v {0 5 -5 1.5} { if {[catch {format $f $v} r]} {set r "err"}; puts -nonewline "[list $f $v $r] " }
  puts ""
}
puts [format {%-05d|%-05x|%-#05x|%-05.1f} 5 5 5 1.5]
set i 0; puts [catch {for {} {$i < 3} {incr i; continue} { puts i=$i }} m]$m
puts [catch {for {} {$i < 3} {error boo} { }} m]$m; puts $errorInfo
# Option words of string compare/equal/map/match: abbreviations and bad ones.
foreach c {{string compare a b c} {string compare -len 2 abc abd} {string compare -no A a} {string compare -length 1 a} {string equal -nocase -length 2 ABx abY} {string map {a b} abba oops} {string map -no {abc 321 Ab * a A} aAbCaBaAbAbcAb} {string match - b c} {string match -n a A} {string map -nocase {a b} A} {string compare -x a b}} { catch $c m; puts [list $c $m] }
