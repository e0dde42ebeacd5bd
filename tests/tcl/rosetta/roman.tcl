proc toRoman n {
    set out ""
    foreach {v s} {1000 M 900 CM 500 D 400 CD 100 C 90 XC 50 L 40 XL 10 X 9 IX 5 V 4 IV 1 I} {
        while {$n >= $v} { append out $s; incr n -$v }
    }
    return $out
}
proc fromRoman s {
    set map {M 1000 D 500 C 100 L 50 X 10 V 5 I 1}
    set total 0; set prev 0
    foreach c [lreverse [split $s ""]] {
        set v [dict get $map $c]
        if {$v < $prev} { incr total -$v } else { incr total $v; set prev $v }
    }
    return $total
}
foreach n {1 4 9 14 40 90 400 1990 2008 2024 3999} { set r [toRoman $n]; puts "$n $r [fromRoman $r]" }
