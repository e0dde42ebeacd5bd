# Case mapping one for one, clock, after, tailcall, encoding, parray.
puts [string toupper straße]; puts [string totitle ßa]; puts [string tolower ΣΑΣ]
puts [string toupper abcdef 1 3]; puts [string totitle "hello WORLD" 0 end]
puts [expr {[clock seconds] > 1700000000}]; puts [expr {[clock milliseconds] > 1700000000000}]
puts [expr {[clock microseconds] > 1700000000000000}]; puts [string is integer [clock clicks]]
after 10; puts ok
proc f {} { tailcall g 5 }; proc g x { return [expr {$x*2}] }; puts [f]
proc cnt n { if {$n == 0} { return done }; tailcall cnt [expr {$n-1}] }; puts [cnt 5000]
puts [catch {tailcall g 1} m]$m
set enc [encoding convertto utf-8 é]; puts [string length $enc]; puts [encoding convertfrom utf-8 $enc]
array set pa {a 1 bb 2}; parray pa
puts [encoding system]
foreach t {0 86399 951782400 1700000000 -86401 4102444800 1234567890} {
  puts [clock format $t -gmt 1]
  puts [clock format $t -format {%Y-%m-%d %H:%M:%S %j %a %A %b %B %u %w %y %C %e %I %p %T %R %D %F %s %%} -gmt 1]
}
