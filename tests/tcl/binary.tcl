# binary format / scan / encode / decode, printed as hex so bytes compare.
proc hex {s} { binary scan $s H* h; return $h }
foreach {fmt args} {
  a5 {abc} A5 {abc} a* {hello} A* {hi} a {xyz}
  b8 {10110001} B8 {10110001} b* {1101} B12 {101} h4 {a1b2} H* {deadBEEF} H3 {abc}
  c {65} c3 {{1 2 3}} c* {{-1 255 256}} s {258} S {258} t {258} s2 {{1 -1}}
  i {16909060} I {16909060} n {16909060} w {72623859790382856} W {72623859790382856} m {1}
  f {1.5} r {1.5} R {1.5} d {-2.25} q {-2.25} Q {-2.25}
  {a3 x2 a1} {ab c} {a4 X2 a1} {abcd z} {a4 @2 a1} {abcd z} {a2 @6} {ab} {a3 X* a1} {abc z}
  {c u} {1} {iu} {-1} {c2 c} {{1 2} 3}
} {
  if {[catch {hex [binary format $fmt {*}$args]} r]} { set r "error: $r" }
  puts [list $fmt $args $r]
}
foreach bad {{c3 {{1 2}}} {x* {}} {@ {}} {y {}} {b2 12} {H2 xz} {i {1.5}} {a}} {
  lassign $bad fmt arg
  catch {binary format $fmt {*}$arg} r; puts [list $fmt $r]
}
set data [binary format H* 0102fffe7f8000ff41424320202000]
foreach fmt {c c* cu* s2 su2 S2 Su2 t i I iu Iu n w W wu a3 A* a* b16 B16 h6 H6 {x2 c} {X c} {@3 c2} {c2 X2 c} f r d q {c3 c3 c3 c3 c3 c3}} {
  set vars {}
  set n 0
  foreach f $fmt { lappend vars v[incr n] }
  catch {unset {*}$vars}
  if {[catch {binary scan $data $fmt {*}$vars} r]} { puts [list $fmt error $r]; continue }
  set out [list $fmt $r]
  foreach v $vars { if {[info exists $v]} { lappend out [set $v] } }
  puts $out
}
puts [catch {binary scan abc a4 x} r]$r
puts [catch {binary scan abc} r]$r
puts [catch {binary scan abc c} r]$r
puts [binary encode base64 "Hello, world!"]
puts [binary encode base64 -maxlen 8 [string repeat abc 10]]
puts [binary decode base64 SGVsbG8sIHdvcmxkIQ==]
puts [hex [binary decode hex "41 42 4a"]]
puts [binary encode hex "\x00\xffA"]
puts [catch {binary decode base64 -strict "SGV*"} r]$r
puts [catch {binary decode hex -strict "4g"} r]$r
foreach x {0 1 -1 127 128 32767 -32768 2147483647 -2147483648 9223372036854775807} {
  binary scan [binary format W $x] W y; binary scan [binary format i $x] i z; binary scan [binary format s $x] su u
  puts [list $x $y $z $u]
}
set f [binary format f 0.1]; binary scan $f f g; puts $g
binary scan [binary format d 1e308] d g; puts $g
binary scan [binary format f 1e40] f g; puts $g
# X at the start of the string stays there (a fuzzer found it underflowing).
puts [string length [binary format X]]
puts [string length [binary format a2XX3X a]]
