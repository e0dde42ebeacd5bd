# string first/last/replace/match on ASCII and UTF-8 text, every index form.
foreach {n h} {ab xxabyyab a a abc ab "" abc ü aüaü üa xüaüa b abcb} {
    puts [list [string first $n $h] [string last $n $h] [string first $n $h 2] [string last $n $h 2] [string first $n $h end-1] [string last $n $h end] [string first $n $h -5] [string last $n $h -1] [string first $n $h 99] [string last $n $h 99]]
}
foreach {s f l r} {abcdef 1 3 XY abcdef 0 end "" aüböc 1 2 Ω aüböc -1 0 Q aüböc 3 1 Z aüböc end end ""} {
    puts [list [string replace $s $f $l $r] [string replace $s $f $l]]
}
foreach {p s} {*901* x9012 a?c abc {[a-c]x} bx {\*a} *a {*[ü]*} aüb A* abc {a[} a[ {*\\} a\\ {} {} {*} {} {[]} x} {
    puts [list [string match $p $s] [string match -nocase $p $s]]
}
# Indexing a string many times (ASCII and not), then using it as a number or a list.
proc rev {s} { set n [string length $s]; set o {}; while {$n} { append o [string index $s [incr n -1]] }; return $o }
puts [list [rev "abc déf ü"] [rev hello] [string range "aüböc" 1 end-1] [string length "aüböc"]]
set x 42; string index $x 0; puts [expr {$x + 1}]
set l "ü a b"; string index $l 0; puts [llength $l]; string index $l 0; puts [lindex $l 0]
set y "ab"; append y "ü"; puts [list [string length $y] [string index $y end]]
