set s "Hello, World"
puts [string length $s][string length ""][string length héllo]
puts [string index $s 0][string index $s end][string index $s 100]|[string range $s 0 4]|[string range $s 7 end]|[string range $s 5 2]|
puts [string toupper $s][string tolower $s][string totitle "hELLO wORLD"]
puts [string equal a a][string equal a b][string equal -nocase A a][string equal -length 2 abc abd]
puts [string compare a b][string compare b a][string compare a a][string compare -nocase A a][string compare ab abc]
puts [string match *o* $s][string match H?llo* $s][string match {[a-c]*} bat][string match -nocase hello* $s][string match {a\*} a*]
puts [string first o $s][string first o $s 5][string first z $s][string last o $s][string last o $s 5]
puts [string trim "  pad  "]|[string trimleft "xxhixx" x]|[string trimright "xxhixx" x]|[string trim "\t\n x \n"]|
puts [string map {a 1 b 2} abcab][string map {abc X a Y} abcab][string map -nocase {A z} aAa]
puts [string repeat ab 3]|[string repeat x 0]|[string reverse hello]|[string cat a b c]|[string replace hello 1 2 XY]
foreach c {integer double boolean alpha digit alnum space upper lower xdigit list true false wordchar} {
    puts "$c: [string is $c 42] [string is $c abc] [string is $c {}] [string is $c -strict {}] [string is $c 1.5] [string is $c yes] [string is $c { }]"
}
puts [string is integer 0x1f][string is double 1e5][string is double abc][string is list "a {b"]
puts [catch {string foo x} m]$m
puts [string bytelength héllo][string wordend "hello world" 1][string wordstart "hello world" 8]
