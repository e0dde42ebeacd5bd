foreach n {0 5 50 9000 -1 255 1024} {
    puts [format "%6d %s %o %x %b" $n [format %b $n] $n $n $n]
}
binary scan [binary format I 305419896] B* bits; puts $bits
puts [string map {0 . 1 #} [format %016b 43981]]
