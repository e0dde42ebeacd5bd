puts [exec echo hello world]
puts [exec echo a b | tr a-z A-Z]
puts [exec sh -c "echo out; echo err >&2" 2>@1]
puts [catch {exec sh -c "echo out; echo err >&2"} m]; puts $m
puts [catch {exec sh -c "echo out; exit 3"} m]; puts $m; puts [lreplace $::errorCode 1 1 PID]
puts [catch {exec sh -c "exit 3"} m]; puts $m; puts [lrange $::errorCode 0 0]
puts [catch {exec no-such-program-xyz} m]; puts $m; puts [lreplace $::errorCode 1 1 PID]
puts [exec cat << "fed in\nlines"]
set f /tmp/rayshell-exec-[pid].txt
exec echo to file > $f
exec echo more >> $f
puts [exec cat < $f]
puts [exec -keepnewline echo kept]|
puts [exec -ignorestderr sh -c "echo quiet"]
puts [exec sh -c "echo x >&2; echo y" |& cat]
set ch [open "|echo piped" r]
puts [gets $ch]
close $ch
set ch [open "|cat > $f" w]
puts $ch "written through a pipe"
close $ch
puts [exec cat $f]
set ch [open "|sh -c {exit 2}"]
puts [catch {close $ch} m]; puts $m
puts [catch {exec} m]; puts $m
puts [catch {exec echo |} m]; puts $m
puts [catch {exec echo >} m]; puts $m
puts [catch {exec -bogus echo} m]; puts $m
puts [llength [exec sleep 0 &]]
puts [exec echo 2>/dev/null hi]
file delete $f
