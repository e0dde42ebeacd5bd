# Random strings through the string and list commands; shared rand() after
# srand keeps tclsh and raytrace on the same inputs.
expr {srand(31337)}
proc pick {l} { lindex $l [expr {int(rand() * [llength $l])}] }
proc rstr {} {
    set s ""
    for {set j [expr {int(rand() * 7)}]} {$j > 0} {incr j -1} {
        append s [pick {a b B c 1 2 10 x9 Z " " - _ . * ? é}]
    }
    return $s
}
proc ridx {} { pick {0 1 2 end end-1 end-3 -1 5 1+1 2-1 end+1} }
for {set i 0} {$i < 300} {incr i} {
    set s [rstr]; set t [rstr]
    set cmds [list \
        [list string range $s [ridx] [ridx]] [list string index $s [ridx]] \
        [list string first $t $s] [list string last [string index $s 0] $s] \
        [list string compare $s $t] [list string equal -nocase $s $t] \
        [list string match $t $s] [list string match -nocase "*[string index $s 0]*" $t] \
        [list string trim $s " -_"] [list string toupper $s] [list string totitle $s] \
        [list string map [list a X $t Y] $s] [list string repeat $t 2] [list string reverse $s] \
        [list string is alpha $s] [list string is digit -strict $s] [list string length $s] \
        [list lrange [split $s {}] [ridx] [ridx]] [list lindex [split $s " "] [ridx]] \
        [list linsert [list $s $t] [ridx] q] [list lreplace [list a b c d] [ridx] [ridx] $s] \
        [list lsearch -glob [list $s $t a b] $t] [list lsearch -exact -all [split $s {}] a] \
        [list join [split $s " "] +] [list concat $s $t] [list split $s "ab"] \
    ]
    foreach c $cmds {
        # Print the command first: tclsh may change a list argument in place.
        puts -nonewline "[list $c] => "
        if {[catch $c r]} { set r "error: $r" }
        puts [list $r]
    }
}
set words {}
for {set i 0} {$i < 200} {incr i} { lappend words [rstr] }
puts [lsort $words]
puts [lsort -dictionary $words]
puts [lsort -unique -nocase $words]
puts [lsort -decreasing $words]
set nums {}
for {set i 0} {$i < 100} {incr i} { lappend nums [expr {int(rand() * 1000) - 500}] }
puts [lsort -integer $nums]
puts [lsort -integer -unique -decreasing $nums]
