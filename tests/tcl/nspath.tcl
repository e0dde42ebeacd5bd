namespace eval lib { proc helper {} { return "lib helper" } }
namespace eval app {
    namespace path ::lib
    proc run {} { return [helper] }
}
puts [app::run]
puts [namespace eval app {namespace path}]
puts [namespace eval app {helper}]
namespace eval app { namespace path {} }
puts [catch {app::run} m]; puts $m
puts [catch {namespace eval app {namespace path ::nope}} m]; puts $m
