# lsearch's options (issue "Tcl 8.6"), against tclsh.
set l {{a 3} {b 1} {c 2} {b 5}}
puts [lsearch -index 0 $l b]
puts [lsearch -all -index 0 $l b]
puts [lsearch -all -inline -index 0 $l b]
puts [lsearch -all -index 1 -integer $l 5]
puts [lsearch -index 1 -subindices -inline $l 2]
puts [lsearch -regexp {apple banana cherry} {an+a}]
puts [lsearch -all -regexp -nocase {Apple apricot Banana} {^a}]
puts [lsearch -not {a a b a} a]
puts [lsearch -start end-1 {a b a b} a]
puts [lsearch -sorted {1 3 5 7} 5]
puts [lsearch -bisect -integer {1 3 5 7} 6]
puts [lsearch -bisect -integer -decreasing {9 7 5 3} 6]
puts [lsearch -bisect {apple banana cherry} b]
puts [lsearch -dictionary -exact {a10 a9} A9]
puts [lsearch -real {1.0 2.5 3} 2.50]
catch {lsearch -index -2 $l b} e; puts $e
catch {lsearch -subindices $l b} e; puts $e
catch {lsearch -bisect -all $l b} e; puts $e
catch {lsearch -foo $l b} e; puts $e
