# regexp, regsub and switch -regexp (issue "Tcl 8.6"), against tclsh.
puts [regexp {(\d+)-(\d+)} "range 10-20 and 30-40" m a b]; puts "$m $a $b"
puts [regexp -all {\d+} "1 22 333"]
puts [regexp -all -inline {\d+} "1 22 333"]
puts [regexp -inline {(a)(b)?} "ac"]
puts [regexp -indices {b+} "abbbc" m]; puts $m
regexp -indices {(x)?(b)} "ab" m g1 g2; puts "$m|$g1|$g2"
puts [regexp -nocase {HELLO} "say hello"]
puts [regexp {^b} "a\nb"] 
puts [regexp -line {^b} "a\nb"]
puts [regexp {a.b} "a\nb"]
puts [regexp -line {a.b} "a\nb"]
puts [regexp {\mfoo\M} "a foo b"]
puts [regexp {\mfoo\M} "afoob"]
puts [regexp {(a)\1} "aa"]
puts [regexp {[[:alpha:]]+} "123abc" m]; puts $m
puts [regexp {[]a]+} "]a]" m]; puts $m
puts [regsub {(\w+) (\w+)} "hello world" {\2 \1}]
puts [regsub -all {o} "foo boo" 0]
puts [regsub -all {a|b} "abc" {<&>}]
puts [regsub {x} "abc" y]
puts [regsub -all {} "abc" -]
set n [regsub -all {\d} "a1b2c3" X r]; puts "$n $r"
puts [regsub -all {\\} {a\b} {/}]
puts [regexp -start 2 {a} "aba"]
puts [regexp -all -start 1 -inline {\w} "abc"]
catch {regexp {(} x} e; puts [string range $e 0 44]
catch {regexp -foo x y} e; puts $e
catch {regexp} e; puts $e
puts [regexp {***=a.b} "a.b"]
puts [regexp {(?i)ABC} "abc"]
puts [regsub -all {(\d+)} "a12b3" {[\1]}]
puts [regexp -all -indices -inline {o} "foo"]
foreach line {"x=1" "y = 22" "bad"} { if {[regexp {^(\w+)\s*=\s*(\d+)$} $line -> k v]} { puts "$k:$v" } else { puts "no: $line" } }
catch {switch -glob -exact a {}} e; puts $e
catch {switch -matchvar m a {}} e; puts $e
switch -regexp -matchvar m -indexvar ix "foo123" {{([a-z]+)(\d+)} {puts "$m | $ix"}}
switch -regexp -- "abc" {^x {puts x} {b.} {puts b} default {puts d}}
switch -regexp -nocase "ABC" {^abc$ {puts yes}}
