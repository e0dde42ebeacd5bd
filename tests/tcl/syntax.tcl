# The twelve rules: separators, words, quoting, substitution.
set a 1; set b 2
puts "$a $b"
puts {$a $b}
puts "nested [list a [list b c]] done"
puts {braces {nest} and \{ escape}
puts "backslash-newline: a\
      b"
puts {inside braces: a\
      b}
puts "escapes: \x41\x4a \101 \u00e9 \t|\q|\\|\$|\[|"
set arr(one) 1; set arr(two) 2; set i one
puts "$arr($i) $arr(two) ${a}x"
set {odd name} 5; puts ${odd name}
puts [string length "a;b"]; puts a;puts b
# a comment \
  continued comment
puts "after comment"
set x "a b"; puts [llength "$x c"]; puts [llength [list {*}$x c]]
puts [list {*}{} x {*}"y z"]
puts "[set a]+[set b]"
puts $a$b[set a]
puts "dollar alone: $ and $ x"
puts {}
puts "\{ \} \[ \]"
set s abc; puts "$s(" ; puts "x]"
puts [list \{a b\}]
puts "unicode: héllo wörld"
puts [expr {"#" eq "#"}]
