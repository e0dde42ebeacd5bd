puts [format "%5.2f|%-5d|%05d|%x|%X|%o|%e|%E|%c" 3.14159 42 42 255 255 8 1234.5 0.000123 65]
puts [format "%g %g %g %g %g %g %G" 0.0001 123456789 100000 1e-10 1e100 0.0 1e-10]
puts [format "%#x %#o %+d % d %+.3f %#g" 255 8 5 5 2.5 1.0]
puts [format "%2\$s %1\$s" a b][format "%s %s" x y][format %%][format "%5s|%-5s|%.2s" ab ab abc]
puts [format "%*d|%-*d|%.*f" 5 42 5 42 2 3.14159]
puts [format "%d %i %u %b" 0x10 -7 -1 5][format %x -1][format %lx -1][format %llx 255]
puts [format "%.0f %.0f %.0f %.1f %.2f" 0.5 1.5 2.5 0.05 1.005]
puts [format "%10.4e|%-12.3g|%012.3f" -3.5 123456 -3.14159]
puts [format "%s" [expr 1.0]][format %c 233][format %5.1f%% 12.34]
puts [format %03d 7][format %.3d 7][format %+05d 7][format "% 05d" 7]
foreach bad {{%d abc} {%d} {%z 1} {%d 1.5} {%s}} { puts [catch [list format {*}$bad] m]:$m }
puts [catch {format %99999999999999999999\$d 1} m]$m
puts [format %x|%X|%o|%b|%#x|%#o|%08x|%-6x|%.5x 255 255 8 5 0 0 255 255 255]
puts [format %llx|%lld|%hx|%hd|%x|%d -1 -99999999999999999999 -1 70000 -1 -5]
puts [format %b|%#b|%o 0 0 0]
puts [catch {format {%5$d} 1} m]$m
puts [format {%2$s-%1$s} a b]
