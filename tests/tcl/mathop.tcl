# tcl::mathop and tcl::mathfunc as commands; functions defined by scripts.
foreach c {{tcl::mathfunc::abs} {tcl::mathfunc::abs 1 2} {tcl::mathfunc::abs x} {tcl::mathfunc::max} {tcl::mathfunc::rand 1} {tcl::mathfunc::pow 1} {tcl::mathop::+} {tcl::mathop::+ 1 2 3} {tcl::mathop::- 5} {tcl::mathop::-} {tcl::mathop::- 10 1 2} {tcl::mathop::* } {tcl::mathop::/ 2.0} {tcl::mathop::/ 7 2 2} {tcl::mathop::/} {tcl::mathop::% 7} {tcl::mathop::** 2 3 2} {tcl::mathop::**} {tcl::mathop::** 3} {tcl::mathop::< 1 2 3} {tcl::mathop::<} {tcl::mathop::< 1} {tcl::mathop::== 1 1.0 1} {tcl::mathop::!= 1 2 1} {tcl::mathop::eq a a} {tcl::mathop::eq a} {tcl::mathop::in a {a b}} {tcl::mathop::in a} {tcl::mathop::& } {tcl::mathop::| 1 2 4} {tcl::mathop::^ 7 1} {tcl::mathop::~ 5} {tcl::mathop::! 0} {tcl::mathop::! 0 1} {tcl::mathop::<< 1 3} {tcl::mathop::>> 8} {tcl::mathop::+ a} {tcl::mathop::- a} {tcl::mathop::% 1 2 3} {namespace exists tcl::mathfunc} {tcl::mathop::ne a b c}} {
  catch $c m; puts "[list $c] -> [list $m]"
}
proc tcl::mathfunc::twice {x} {expr {2*$x}}
puts [expr {twice(4)+1}]
puts [lsort [info functions]]
foreach op {+ - * / % ** == != < <= > >= eq ne & | ^ << >>} {
  foreach {a b} {7 3 -7 2 2.5 4 0x10 2 abc abd 3 3.0} {
    if {[catch {tcl::mathop::$op $a $b} r]} { set r "error: $r" }
    if {[catch {expr "\$a $op \$b"} e]} { set e "error: $e" }
    puts [list $op $a $b $r [expr {$r eq $e}]]
  }
}
puts [tcl::mathop::+ 1 2 3 4 5] ; puts [tcl::mathop::* 2 3 4.0]; puts [tcl::mathop::- 100 1 2 3]
puts [tcl::mathop::< 1 2 2 3]; puts [tcl::mathop::<= 1 2 2 3]; puts [tcl::mathop::eq a a a]
namespace import ::tcl::mathop::*
puts [+ [* 2 3] [- 10 4]]
proc tcl::mathfunc::clamp {x lo hi} { expr {max($lo, min($x, $hi))} }
puts [expr {clamp(15, 0, 10) + clamp(-3, 0, 10)}]
puts [catch {expr {nosuch(1)}} m]$m
puts [expr {0 && nosuch(1)}]
puts [catch {expr {abs()}} m]$m
