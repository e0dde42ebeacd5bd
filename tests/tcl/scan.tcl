# scan: every conversion, widths, suppression, XPG positions, sets, and
# the return values at the end of the input.
foreach {str fmt} {
  {12 34} {%d %d}  {-12abc} {%d%s}  {0x1f 017 0b11 99} {%i %i %i %i}  {ff 777 101} {%x %o %b}
  {3.5e2 .5 -1.} {%f %e %g}  {abc def} {%s %s}  {abcdef} {%3s%s}  {12345} {%2d%3d}  {A} {%c}
  {  x} {%c}  {hello world} {%[a-z]%n}  {abc123} {%[^0-9]%d}  {]x} {%[]x]}  {a-b} {%[a-]}
  {12 34 56} {%*d %d %d}  {12 34} {%2$d %1$d}  {1 2} {%d %d %d}  {} {%d}  {   } {%d}  {x} {%d}
  {12} {%d%s}  {99999999999999999999} {%d}  {99999999999999999999} {%lld}  {-99999999999999999999} {%d}
  {18446744073709551615} {%d}  {-1} {%u}  {4294967295} {%ld}  {abc} {%c%c%c%c}  {1.5x} {%f%c}
  {inf nan} {%f %f}  {12:34:56} {%d:%d:%d}  {100%} {%d%%}  {1,2} {%d,%d}  {+5 -0} {%d %d}
  {0x} {%i%s}  {08} {%i%s}  {1e} {%f%s}  {12} {%1d%1d%1d}
} {
  if {[catch {scan $str $fmt} r]} { set r "error: $r" }
  puts [list $str $fmt $r]
}
puts [scan "3 4" "%d %d" a b]; puts "$a $b"
puts [scan "" "%d" a]
puts [scan "x" "%d" a]
puts [scan "7" "%d %d" a b]; puts [info exists b]
foreach bad {{%d %d} {%1$d %d} {%z} {%ld %lld} {%2c} {%lls} {%llu} {%[a} {%3$d} {%1$d %1$d}} {
  catch {scan "1 2" $bad x} r; puts [list $bad $r]
}
catch {scan "1 2" {%1$d %1$d}} r; puts $r
catch {scan "1 2" {%2$d}} r; puts $r
catch {scan "1 2" {%d} x y} r; puts $r
