foreach {s f} {
  2024-03-01 ""  "2024-03-01 12:30:45" ""  2024-03-01T12:30:45 ""  20240301 ""  20240301T123045 ""
  03/01/2024 ""  "1 March 2024" ""  "March 1, 2024" ""  "2000-02-29 23:59:59" ""
  "2024-03-01 10:00" "%Y-%m-%d %H:%M"  "01.03.24" "%d.%m.%y"  "Mar 5 2021 3:04 PM" "%b %d %Y %I:%M %p"
  "1700000000" "%s"  "2024 060" "%Y %j"  "12:30:00 2024-01-02" "%T %Y-%m-%d"
} {
  if {$f eq ""} { set t [clock scan $s -gmt 1] } else { set t [clock scan $s -format $f -gmt 1] }
  puts "$s -> $t [clock format $t -format {%Y-%m-%d %H:%M:%S} -gmt 1]"
}
set base [clock scan 2024-01-31 -gmt 1]
foreach {n u} {1 month 1 months 13 months -1 month 1 year 2 days 3 weeks 5 hours 90 minutes 30 seconds} {
  puts "$n $u: [clock format [clock add $base $n $u -gmt 1] -format {%Y-%m-%d %H:%M:%S} -gmt 1]"
}
puts [clock format [clock add [clock scan 2024-02-29 -gmt 1] 1 year 1 day -gmt 1] -gmt 1 -format %D]
puts [clock scan 12:00 -base 86400 -gmt 1]
puts [catch {clock scan "not a date" -gmt 1} m]; puts [string match "unable to convert date-time string*" $m]
puts [catch {clock scan 2024-01-01 -format %d/%m -gmt 1} m]; puts $m
puts [catch {clock add 0 1 fortnight} m]; puts $m
