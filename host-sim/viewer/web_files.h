// Which file of the page a URL path names. Only plain names inside the web
// root are served (no folders, no dot files), so no request can reach
// anything else on the machine.
#pragma once

#include <string>
#include <string_view>

namespace troupe::viewer {

/// The file name for a request target ("/" is index.html; a query string is
/// ignored), or empty when the target is not a servable name.
std::string web_file_name(std::string_view target);

/// The Content-Type for a file name, by extension.
std::string_view content_type(std::string_view name);

}  // namespace troupe::viewer
