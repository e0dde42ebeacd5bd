# Parse a small config file written and read back through a channel.
set path [file join [file dirname [info script]] config_tmp.txt]
set f [open $path w]
puts $f "# a comment\nname = rayshell\n  threads=4\nratio = 1.5\n\nflags = fast safe\n"
close $f
set f [open $path]
set cfg [dict create]
while {[gets $f line] >= 0} {
    if {[regexp {^\s*(#|$)} $line]} continue
    if {[regexp {^\s*(\w+)\s*=\s*(.*?)\s*$} $line -> k v]} { dict set cfg $k $v }
}
close $f
file delete $path
dict for {k v} $cfg { puts "$k -> $v" }
puts [expr {[dict get $cfg threads] * [dict get $cfg ratio]}]
try { dict get $cfg missing } on error {msg opts} { puts "error: $msg ([dict get $opts -errorcode])" }
