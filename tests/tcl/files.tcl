# file, glob, pwd and cd against tclsh: names, a small tree made, listed,
# copied, renamed and deleted under a fresh directory.
foreach n {/a/b/c.txt a/b c /c / {} a.b/c .bashrc x.tar.gz a//b/ ~user/x ./a} {
  puts [list $n [file dirname $n] [file tail $n] [file extension $n] [file rootname $n] [file split $n] [file pathtype $n]]
}
puts [file join a b c]; puts [file join a /b c]; puts [file join a/ b/ c/]; puts [file join /]
set tmp /tmp/rayshell-files-[pid]
file mkdir $tmp/sub/deep
set cwd [pwd]
cd $tmp
foreach f {a.txt b.txt c.tcl sub/d.txt sub/deep/e.txt .hidden} { set h [open $f w]; puts -nonewline $h $f; close $h }
puts [lsort [glob *]]
puts [lsort [glob *.txt]]
puts [lsort [glob -nocomplain *.none]]
puts [lsort [glob */*.txt]]
puts [lsort [glob -types d *]]
puts [lsort [glob -types f -directory sub *]]
puts [lsort [glob -tails -directory sub *]]
puts [lsort [glob {*.{txt,tcl}}]]
puts [lsort [glob .* *]]
puts [catch {glob *.none} m]$m
puts [catch {glob *.none *.nix} m]$m
puts [list [file exists a.txt] [file isfile a.txt] [file isdirectory sub] [file isfile sub] [file size a.txt] [file type sub] [file type a.txt] [file readable a.txt] [file writable a.txt] [file executable a.txt]]
file copy a.txt copy.txt
file rename b.txt sub/
puts [lsort [glob -nocomplain * sub/*]]
puts [catch {file copy a.txt copy.txt} m]$m
file copy -force a.txt copy.txt
puts [catch {file delete sub} m]$m
file delete -force sub
file delete a.txt nonexistent
puts [lsort [glob -nocomplain *]]
puts [expr {[file mtime copy.txt] > 0}]
puts [string equal [file normalize copy.txt] $tmp/copy.txt]
puts [string equal [file normalize ./x/../copy.txt] $tmp/copy.txt]
cd $cwd
puts [string equal [pwd] $cwd]
puts [catch {cd /nonexistent/dir} m]$m
file delete -force $tmp
puts [file exists $tmp]
puts [catch {file size /nonexistent} m]$m
puts [catch {file bogus x} m]$m
