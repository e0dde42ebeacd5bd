puts "before"
proc helper {} {
    sphre 1 2 3
}
helper
puts "never"
