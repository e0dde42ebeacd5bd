namespace eval matrix {
    namespace export mul transpose display
    proc transpose m {
        set t {}
        for {set c 0} {$c < [llength [lindex $m 0]]} {incr c} { lappend t [lmap row $m { lindex $row $c }] }
        return $t
    }
    proc mul {a b} {
        set bt [transpose $b]
        lmap row $a { lmap col $bt { tcl::mathop::+ {*}[lmap x $row y $col { expr {$x*$y} }] } }
    }
    proc display m { foreach row $m { puts [join [lmap x $row { format %6s $x }] ""] } }
}
namespace import matrix::*
set a {{1 2 3} {4 5 6}}
set b {{7 8} {9 10} {11 12}}
display [mul $a $b]
display [transpose $a]
