#pragma once
// A database URL as it may be shown: libpq's URI (postgresql://user:password@host/db) and
// key=value (password=...) forms with the password replaced by "***".
#include <string>

namespace tlsmon {

std::string redacted_url(const std::string& url);
// True when `url` carries a password in either form.
bool url_has_password(const std::string& url);

}  // namespace tlsmon
