# Random expressions, numbers and formats: tclsh and raytrace share rand()
# after srand, so both evaluate the same ones; results must agree.
expr {srand(99)}
proc pick {l} { lindex $l [expr {int(rand() * [llength $l])}] }
proc operand {} {
    switch [expr {int(rand() * 5)}] {
        0 { return [expr {int(rand() * 200) - 100}] }
        1 { return [expr {rand() * 100 - 50}] }
        2 { return [format %.3g [expr {rand() * 1e6}]] }
        3 { return [expr {int(rand() * 10)}] }
        default { return [pick {0 1 -1 2.5 0x1f 010 1e3 .5}] }
    }
}
for {set i 0} {$i < 600} {incr i} {
    set e "[operand] [pick {+ - * / % < <= == != && || & | ^ << >> eq ne}] [operand]"
    if {[catch {expr $e} r]} { set r "error: $r" }
    puts "$e => $r"
}
foreach f {sin cos tan exp log sqrt abs floor ceil round int double} {
    for {set i 0} {$i < 20} {incr i} {
        set x [expr {rand() * 20 - 5}]
        if {[catch {expr "${f}($x)"} r]} { set r "error: $r" }
        puts "$f $x => $r"
    }
}
for {set i 0} {$i < 300} {incr i} {
    set x [expr {(rand() - 0.5) * 10.0 ** int(rand() * 40 - 20)}]
    set spec [pick {%g %e %f %.2f %10.4e %-8.3g %G %.0f %#g %+.5e %.15g %.17g}]
    puts "$x [format $spec $x]"
}
# Powers that stay within 64 bits (rayshell does not have bignums).
for {set i 0} {$i < 100} {incr i} {
    set b [expr {int(rand() * 21) - 10}]; set x [expr {int(rand() * 12) - 2}]
    if {[catch {expr {$b ** $x}} r]} { set r "error: $r" }
    puts "$b ** $x => $r"
}
