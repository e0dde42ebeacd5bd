puts "$argc [llength $argv]"
