# Channels on files: write, read back by lines and in pieces, seek, tell,
# eof, append, binary, and the errors.
set dir [file dirname [info script]]
set f [open $dir/chan_tmp.txt w]
puts $f "first line"
puts -nonewline $f "second"
puts $f " line\r\nthird\rfourth"
puts $f "ünïcödé"
close $f
set f [open $dir/chan_tmp.txt]
while {[gets $f line] >= 0} { puts [list $line [eof $f]] }
puts [list eof [eof $f] [gets $f] [gets $f x] $x]
close $f
set f [open $dir/chan_tmp.txt r]
puts [list [read $f 5] [tell $f]]
seek $f 0
puts [list [gets $f] [tell $f]]
seek $f -6 end
puts [list [read $f]]
seek $f 2 start; seek $f 3 current
puts [list [read $f 4] [tell $f]]
close $f
set f [open $dir/chan_tmp.txt a]
puts $f appended
close $f
set f [open $dir/chan_tmp.txt]
puts [list [read -nonewline $f]]
close $f
set f [open $dir/chan_tmp.txt w+]
puts -nonewline $f abcdef
seek $f 2
puts [read $f]
close $f
set f [open $dir/chan_tmp.txt w]
fconfigure $f -translation binary
puts -nonewline $f [binary format c* {0 1 255 13 10 65}]
close $f
set f [open $dir/chan_tmp.txt rb]
binary scan [read $f] c* bytes; puts $bytes
close $f
set f [open $dir/chan_tmp.txt]
fconfigure $f -translation binary
puts [string length [read $f]]
puts [fconfigure $f -translation]
close $f
foreach c {
  {open /nonexistent/x}
  {open /tmp x}
  {gets nosuch}
  {close nosuch}
  {read stdout}
  {puts stdin x}
  {seek stdin 0 middle}
} { catch $c m; puts [list $c $m $::errorCode] }
set f [open $dir/chan_tmp.txt w]
puts [catch {gets $f} m]$m
close $f
puts [catch {puts $f x} m]$m
set f [open $dir/chan_tmp.txt {WRONLY TRUNC}]
puts $f posix
close $f
set f [open $dir/chan_tmp.txt RDONLY]; puts [gets $f]; close $f
puts [lsort [chan names std*]]
file delete $dir/chan_tmp.txt
puts [file exists $dir/chan_tmp.txt]
# Bytes that are not UTF-8 count as one character each when reading by count.
set f [open $dir/chan_tmp2.txt wb]; puts -nonewline $f "\xff\xfeab\xe2\x82\xacc\r\nd"; close $f
set f [open $dir/chan_tmp2.txt]
fconfigure $f -encoding utf-8
set a [read $f 2]; set t1 [tell $f]; set b [read $f 4]; set t2 [tell $f]; set c [read $f]
puts [list [string length $a] $t1 [string length $b] $t2 [string length $c] [eof $f]]
close $f
file delete $dir/chan_tmp2.txt
