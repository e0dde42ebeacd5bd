# Compiled proc bodies (src/interp/compile.rs) must behave exactly as the
# uncompiled interpreter and as tclsh: control flow, variables by slot and
# by name, redefinition of the builtins they inline, traces, errors.

proc ret_in_subst {} { set x [return 5]; puts notreached }
puts [ret_in_subst]
proc ret_in_loop {} {
    for {set i 0} {$i < 5} {incr i} { if {$i == 2} { return [list got $i] } }
}
puts [ret_in_loop]
proc loop_ctl {} {
    set l {}
    foreach x {1 2 3 4 5 6} {
        if {$x == 2} continue
        if {$x == 5} break
        lappend l $x
    }
    set j 0
    while 1 { incr j; if {$j >= 3} break }
    lappend l $j
}
puts [loop_ctl]
proc break_in_next {} {
    set s 0
    for {set i 0} {$i < 10} {incr i; if {$i > 5} break} { incr s $i }
    return $s
}
puts [break_in_next]
proc stray_break {} { break }
puts [list [catch stray_break m] $m]
proc stray_continue {} { if 1 { continue } }
puts [list [catch stray_continue m] $m]
proc subst_break {} { foreach x {1 2 3} { set y [break] }; return after }
puts [subst_break]

# Variables: links made by upvar, global and variable are slots too.
proc via_upvar {} { set y 1; upvar 0 y z; incr z 5; append z !; return $y }
puts [via_upvar]
set g 10
proc via_global {} { global g; incr g; lappend g x; set g }
puts [via_global]; puts $g
proc caller {} { set v 1; callee; return $v }
proc callee {} { upvar 1 v w; incr w 100 }
puts [caller]
proc up_elem {} { set a(k) 1; upvar 0 a(k) e; incr e; set e 7; return $a(k) }
puts [up_elem]
proc unset_reset {} {
    set x 1
    unset x
    set r [info exists x]
    set x 2
    lappend r $x [info exists x]
}
puts [unset_reset]
proc arrays {} {
    set a(1) one
    set k 2
    set a($k) two
    incr a(n)
    incr a(n) 4
    append a(s) x y
    lappend a(l) p q
    list [lsort [array names a]] $a(1) $a($k) $a(n) $a(s) $a(l)
}
puts [arrays]
proc array_as_scalar {} { set a(1) 1; set a }
puts [list [catch array_as_scalar m] $m]
proc scalar_as_array {} { set s 1; set s(1) 2 }
puts [list [catch scalar_as_array m] $m]
proc no_such {} { set r $nope }
puts [list [catch no_such m] $m]
proc vars_order {a b} { set z 1; set y 2; global g; list [info vars] [info locals] }
puts [vars_order 1 2]
proc incr_new {} { incr fresh; incr fresh 2; set fresh }
puts [incr_new]
proc incr_bad {} { set x abc; incr x }
puts [list [catch incr_bad m] $m]
proc incr_big {} { set x 9223372036854775807; incr x; incr x -1; incr x 10 }
puts [incr_big]
proc incr_shared {} { set a 1; set b $a; incr a; lappend l $a; incr a; list $a $b $l }
puts [incr_shared]
proc args_default {a {b 2} args} { list $a $b $args }
puts [args_default 1]; puts [args_default 1 3 4 5]
proc too_many {a} {}
puts [list [catch {too_many 1 2} m] $m]

# expr on locals: numbers as numbers, strings as strings.
proc exprs {} {
    set h 0x10
    set d 2.5
    set s abc
    set i 7
    list [expr {$h + 1}] [expr {$h eq "16"}] [expr {$h == 16}] [expr {$d * 2}] \
        [expr {$s eq "abc"}] [expr {$s < "abd"}] [expr {$i / 2}] [expr {-$i % 3}] \
        [expr {$i > 5 ? "big" : "small"}] [expr {$i & 3}] [expr {double($i)}] \
        [expr {$i ** 2}] [expr {$i << 62}] [expr {sqrt($i*$i)}] [expr {$i in {1 7}}]
}
puts [exprs]
proc expr_errors {} {
    set r {}
    set z 0
    lappend r [catch {expr {1 / $z}} m] $m
    set s abc
    lappend r [catch {expr {$s + 1}} m] $m
    lappend r [catch {expr {sqrt(-1)}} m] $m
}
puts [expr_errors]

# Redefining a builtin the body inlines, even mid-body, takes effect at once.
proc redefine {} {
    set x 1
    rename set _set
    proc set {args} { return "my set $args" }
    _set r [set x 2]
    rename set {}
    rename _set set
    list $x $r
}
puts [redefine]
namespace eval ns {
    proc set {args} { return "ns set $args" }
    proc p {} { set x 1 }
    proc incr {args} { return "ns incr $args" }
    proc q {} { incr y }
}
puts [ns::p]; puts [ns::q]
proc later {} { if {[llength [info commands while]]} { return [while 0 {}] } }
puts [list [later]]
rename while _while
proc while {args} { return "fake while" }
puts [later]
rename while {}
rename _while while
puts [list [later]]

# Traces see every access of a compiled local.
proc traced {} {
    set x 1
    trace add variable x write {apply {args {puts "write [lindex $args 0]"}}}
    trace add variable x read {apply {args {puts "read [lindex $args 0]"}}}
    set x 2
    incr x
    lappend x 3
    set y [expr {$x}]
    return $y
}
puts [traced]
proc stepped {} { set a 1; incr a; return $a }
trace add execution stepped enterstep {apply {{cmd op} {puts "step: $cmd"}}}
puts [stepped]

# Errors: the innermost command and the proc line, as tclsh logs them.
proc deep_error {} {
    set x 1
    while {$x < 100} {
        set x [expr {$x * 2}]
        if {$x > 30} {
            error "big $x"
        }
    }
}
catch deep_error m; puts $m; puts $::errorInfo
proc bad_in_word {} {
    foreach i {1 2} {
        set v [lindex {a b} $i $i $i]
    }
    set w [nosuchcommand $v]
}
catch bad_in_word m; puts $m; puts $::errorInfo

# Recursion through compiled bodies counts proc levels as Tcl does.
proc depth {n} { if {$n} { return [depth [expr {$n - 1}]] }; return done }
puts [depth 900]
proc fib {n} { if {$n < 2} { return $n }; expr {[fib [expr {$n - 1}]] + [fib [expr {$n - 2}]]} }
puts [fib 20]

# Nesting deeper than the compiler inlines still runs.
set body {set r deep}
for {set i 0} {$i < 80} {incr i} { set body "if 1 {$body}" }
proc nested {} "$body; return \$r"
puts [nested]
# A call refused for its argument count leaves nothing for the next one.
proc two {a b} { list $a $b }
proc one args { lindex $args 0 }
catch {two 1}
puts [one x][two p q]
# Locals hold numbers unboxed: read as values, incremented, appended to.
proc nums {} {
    set i 0; set d 0.5; set s [expr {$d * 3}]
    for {set k 0} {$k < 3} {incr k} { incr i; set d [expr {$d + 0.25}] }
    append i 7; lappend l $i $d $s
    set n 9223372036854775806; incr n; set big [catch {incr n} e]
    list $l $n $big [expr {$i + 1}] [string length $d]
}
puts [nums]
# Local arrays: elements by slot, the array by name too.
proc arr {} {
    set k x
    set a(1) one; set a($k) two; set a(y$k) three; set a() empty
    incr a(n); incr a(n) 4; incr a($k$k) 2
    lappend r $a(1) $a($k) $a(y$k) $a() $a(n) $a(xx) [set a(1)]
    lappend r [lsort [array names a]] [array size a] [info exists a(zz)]
    set s 5
    lappend r [catch {set s(1) 2} e] $e [catch {set a} e] $e [catch {set a(q)} e] $e
    lappend r [catch {incr a(1)} e] $e
    upvar 0 a(1) one; set one ONE; lappend r $a(1)
    unset a(1); lappend r [info exists a(1)] [catch {set a(1)} e] $e
    array set b {p 1 q 2}; incr b(p) 10; lappend r $b(p) "[set b(q)]!"
    return $r
}
puts [arr]
# foreach with several variables and lists (compiled in general).
proc fe {} {
    set r {}
    foreach {x y z} {1 2 3 4 5 6 7} { lappend r "$x,$y,$z" }
    foreach a {1 2 3} {b c} {p q r s t} { lappend r [list $a $b $c] }
    foreach {a b} {} c {u v} { lappend r [list $a $b $c] }
    foreach i {1 2 3 4} j {a b c d} { if {$i == 2} continue; if {$i == 4} break; lappend r $i$j }
    lappend r [catch {foreach i {1 2} j "a \{b" {}} e] $e $i
    array set arr {}
    lappend r [catch {foreach {k arr} {1 2} {}} e] $e $k
    lappend r [catch {foreach {} {1 2} {}} e] $e
    set n 0
    foreach {x y} [list [incr n] [incr n] [incr n]] w [list $n] { lappend r $x/$y/$w }
    lappend r [foreach {p q} {1 2} {}] [lsort [info locals]]
    return $r
}
puts [fe]
proc fe_ret {} { foreach {a b} {1 2 3 4} c {x y} { if {$a == 3} { return $b$c } } }
puts [fe_ret]
# append and lappend to local array elements.
proc ae {} {
    set k x
    lappend a(1) p q; lappend a(1) r; lappend a($k) {s t}; append a(s$k) u v; append a(s$k) w
    lappend r $a(1) $a($k) $a(s$k) [lsort [array names a]] [lappend a(1)] [append a(sx)]
    set a(bad) "a \{"
    lappend r [catch {lappend a(bad) z} e] $e $a(bad)
    set s 1
    lappend r [catch {lappend s(1) z} e] $e [catch {append s(1) z} e] $e
    upvar 0 a(1) one; lappend one END; lappend r $a(1)
    foreach {c v} {p 1 q 2 p 3} { lappend g($c) $v }
    lappend r [array get g]
    return $r
}
puts [ae]
# Expanded words in commands the compiler calls straight.
proc p {} { set l {{a b}}; set m {x {y z}}; list [llength {*}$l] [list {*}$m q] [lindex {*}$l 1] [string length {*}$l] [catch {llength {*}$m} e] $e [join {*}$l -] }
puts [p]
# string is -failindex, called straight, sets its variable (and its trace fires).
proc p {} { set r [string is integer -failindex bad 12x]; list $r $bad [info locals] }
puts [p]
proc q {} { trace add variable w write {apply {args {puts traced}}}; string is integer -failindex w 1x; set w }
puts [q]
# One-word append and lappend (moved in), incr of an array element in
# place: a value another variable holds is never changed.
proc one {} {
    set l {a b}; set keep $l; lappend l c; append s x; set t $s; append s y
    set a(k) 5; set b $a(k); incr a(k) 2; incr a(k); set c $a(k); incr a(k)
    lappend r $l $keep $s $t $a(k) $b $c [lappend u [list 1 2]] [llength $u]
    set n 7; lappend n 8; set m 1.5; append m 0
    set e "x \{"; lappend r [catch {lappend e z} msg] $msg $n $m
    trace add variable w write {apply {args {puts w-traced}}}
    lappend w 1; append w 2; lappend r $w
    set q(k) 1; trace add variable q read {apply {args {puts q-read}}}; incr q(k) 3
    lappend r $q(k) "key[expr {2 * 3}]$n" "[string repeat ab 20][set n]"
    return $r
}
puts [one]
# lset in place: another variable holding the list keeps its value; bad
# indices and non-lists leave the variable as it was; traces see it.
proc lsetcases {} {
    set l {a b c}; set keep $l
    lset l 1 B; lset l end C; lset l 3 d
    lappend r $l $keep [catch {lset l 9 x} e] $e $l
    set s "x  {y z}"; lset s 0 X; lappend r $s
    set bad "a \{"; lappend r [catch {lset bad 0 z} e] $e $bad
    set n {1 {2 3}}; lset n 1 0 two; lset n {1 1} three; lappend r $n [catch {lset n 1 5 q} e] $e $n
    set w {p q}; lset w {} whole; lappend r $w [lset w new]
    set big {}; for {set i 0} {$i < 2000} {incr i} { lappend big $i }
    for {set i 0} {$i < 2000} {incr i} { lset big $i [expr {$i * 2}] }
    lappend r [lindex $big 1999] [llength $big]
    trace add variable t {read write} {apply {{n1 n2 op} {puts "trace $op"}}}
    set t {1 2}; lset t 0 one; lappend r $t
    lappend r [catch {lset nosuch 0 x} e] $e
    array set arr {k v}; lappend r [catch {lset arr 0 x} e] $e
    return $r
}
puts [lsetcases]
# lreplace of an unshared list (the K idiom) changes it in place; what
# another variable holds, an error, and an execution trace see no change.
proc K {x y} { set x }
proc p {} {
    set l {}; for {set i 0} {$i < 10} {incr i} { lappend l $i }
    set keep $l
    set l [lreplace [K $l [set l {}]] 2 3 X]
    set m {}; for {set i 0} {$i < 5} {incr i} { lappend m $i }
    set n [lreplace [K $m [set m {}]] 0 0]
    set s [lreplace [list a b c] 1 1 B]
    set e [catch {lreplace [K $n [set n {}]] x 1} msg]
    list $l $keep $n $s $e $msg [lreplace {a b c} end end] [lreplace {} 0 0 z]
}
puts [p]
trace add execution lreplace leave {apply {{cmd code res op} {puts "leave: $cmd"}}}
proc q {} { set l [list 1 2 3]; lreplace [K $l [set l {}]] 0 0 zero }
puts [q]
# foreach with a variable list of several names and one list (compiled),
# lindex with a literal index word, comparisons with an empty string,
# binary scan of one value per byte.
proc f3 {} {
    set out {}
    foreach {x y z} {1 2 3 4 5} { lappend out [list $x $y $z] }
    foreach {k v} [list a 1 b 2] { lappend out $k=$v }
    set L {A B C D}
    lappend out [lindex $L 2] [lindex $L end-1] [lindex $L {1}] [lindex {{a b} c} {0 1}]
    lappend out [catch {lindex $L x} msg] $msg
    set n 5; set e {}; set d 1.5
    lappend out [expr {$n != {}}] [expr {$e == {}}] [expr {$n < {}}] [expr {$d > "abc"}] [expr {10 < "9a"}]
    binary scan "\x01\xff\x80AB" c*cu X Y
    lappend out $X [binary scan "\x01\x02\x03\x04" Su2 W] $W
    binary scan "\x00\x00\xc0\x3f\x00\x00\x00\x00\x00\x00\xf8\x3f" rQ F D
    lappend out $F $D
}
puts [f3]
