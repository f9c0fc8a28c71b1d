#include "core/redacted_url.hpp"

#include <regex>

namespace tlsmon {

std::string redacted_url(const std::string& url) {
    static const std::regex uri_password(R"(^(postgres(?:ql)?://[^:@/]*):[^@/]*@)");
    static const std::regex keyword_password(R"((password\s*=\s*)('[^']*'|[^\s&]+))");
    return std::regex_replace(std::regex_replace(url, uri_password, "$1:***@"), keyword_password,
                              "$1***");
}

bool url_has_password(const std::string& url) {
    return redacted_url(url) != url;
}

}  // namespace tlsmon
