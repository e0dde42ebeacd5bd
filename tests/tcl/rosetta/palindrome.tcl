proc palindrome? s {
    set s [string tolower [regsub -all {[^[:alnum:]]} $s ""]]
    expr {$s eq [string reverse $s]}
}
foreach s {racecar "A man, a plan, a canal: Panama" hello "Was it a car or a cat I saw?" ""} {
    puts [format "%-32s %s" "\"$s\"" [expr {[palindrome? $s] ? "yes" : "no"}]]
}
