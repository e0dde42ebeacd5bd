# `string is integer|wideinteger|entier -failindex`: where a number stops
# being readable, and -1 for one readable whole but too big (issue
# "untrusted scenes", finding 15: this was cubic in the digits).
foreach cls {integer wideinteger entier} {
    foreach s {99999999999 12a 4294967296 -4294967295 " 12 x" 0x1ffffffff 1e5 ""
            99999999999a 0x 0xg 0b102 "  " "- 1" + 0o78 1_000 " 0x1f  " "1 2" 0d19a
            00012a 08 -0 +0x10 99999999999999999999999 99999999999999999999999z
            0b1111111111111111111111111111111111111111111111111111111111111111
            0b11111111111111111111111111111111111111111111111111111111111111111
            0o1777777777777777777777 0o2000000000000000000000 9223372036854775807
            -9223372036854775808 18446744073709551615 18446744073709551616} {
        set r [string is $cls -failindex i $s]
        if {![info exists i]} {set i none}
        puts "$cls {$s} $r $i"
        unset i
    }
}
# Long numbers answer at once (tclsh is linear too).
set s [string repeat 7 200000]
puts [string is integer -strict -failindex i $s]/$i
puts [string is integer -failindex i ${s}x]/$i
puts [string is entier $s]
