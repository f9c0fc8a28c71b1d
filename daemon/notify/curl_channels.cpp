// E-mail (SMTP, RFC 5321 with STARTTLS, RFC 3207) and webhook (HTTP POST) channels through
// libcurl: the only file that includes it.
#include <curl/curl.h>
#include <openssl/evp.h>
#include <unistd.h>

#include <cstring>
#include <ctime>
#include <memory>
#include <mutex>

#include "daemon/notify/notification_channel.hpp"
#include "daemon/notify/notification_message.hpp"

namespace tlsmon {

namespace {

// curl_global_init is not thread-safe: once, before the first handle.
void global_init() {
    static std::once_flag once;
    std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

struct Easy {
    Easy() : handle(curl_easy_init()) {
        if (!handle) throw Error("libcurl: cannot create a handle");
        error[0] = '\0';
        curl_easy_setopt(handle, CURLOPT_ERRORBUFFER, error);
        curl_easy_setopt(handle, CURLOPT_NOSIGNAL, 1L);  // threads: no SIGALRM for timeouts
    }
    ~Easy() {
        curl_easy_cleanup(handle);
        curl_slist_free_all(list_a);
        curl_slist_free_all(list_b);
    }
    Easy(const Easy&) = delete;
    Easy& operator=(const Easy&) = delete;

    // Runs the transfer; an Error with libcurl's reason, prefixed by `what`.
    void perform(const std::string& what) {
        const CURLcode rc = curl_easy_perform(handle);
        if (rc != CURLE_OK) {
            throw Error(what + ": " + (error[0] ? std::string(error) : curl_easy_strerror(rc)));
        }
    }

    CURL* handle;
    curl_slist* list_a = nullptr;
    curl_slist* list_b = nullptr;
    char error[CURL_ERROR_SIZE];
};

void common_options(Easy& e, const NotifyChannel& c) {
    curl_easy_setopt(e.handle, CURLOPT_URL, c.url.c_str());
    curl_easy_setopt(e.handle, CURLOPT_TIMEOUT_MS, static_cast<long>(c.timeout * 1000));
    curl_easy_setopt(e.handle, CURLOPT_CONNECTTIMEOUT_MS, static_cast<long>(c.timeout * 1000));
    if (!c.ca_file.empty()) curl_easy_setopt(e.handle, CURLOPT_CAINFO, c.ca_file.c_str());
}

// The message body handed to libcurl's upload, piece by piece.
struct Upload {
    const std::string* text;
    std::size_t at = 0;
};
std::size_t read_upload(char* buffer, std::size_t size, std::size_t count, void* user) {
    auto* u = static_cast<Upload*>(user);
    const std::size_t n = std::min(size * count, u->text->size() - u->at);
    std::memcpy(buffer, u->text->data() + u->at, n);
    u->at += n;
    return n;
}
std::size_t keep_reply(char* data, std::size_t size, std::size_t count, void* user) {
    auto* out = static_cast<std::string*>(user);
    if (out->size() < 512) out->append(data, std::min<std::size_t>(size * count, 512));
    return size * count;
}

bool plain_ascii(const std::string& s) {
    for (unsigned char c : s) {
        if (c < 0x20 || c > 0x7e) return false;
    }
    return true;
}

// A header's text: as is when printable ASCII, else an RFC 2047 encoded word (UTF-8, base64).
std::string header_text(const std::string& s) {
    if (plain_ascii(s)) return s;
    std::string b64(4 * ((s.size() + 2) / 3) + 1, '\0');
    const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(b64.data()),
                                  reinterpret_cast<const unsigned char*>(s.data()),
                                  static_cast<int>(s.size()));
    b64.resize(static_cast<std::size_t>(n));
    return "=?UTF-8?B?" + b64 + "?=";
}

// RFC 5322 date: "Sun, 29 Nov 2026 12:31:29 +0000".
std::string mail_date(UtcSeconds t) {
    const std::time_t tt = static_cast<std::time_t>(t);
    std::tm tm{};
    gmtime_r(&tt, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, "%a, %d %b %Y %H:%M:%S +0000", &tm);
    return buf;
}

// Lines end in CRLF (RFC 5322 §2.1); libcurl dot-stuffs lines that begin with ".".
std::string crlf(const std::string& text) {
    std::string out;
    out.reserve(text.size() + text.size() / 40);
    for (char c : text) {
        if (c == '\n') out += '\r';
        out += c;
    }
    return out;
}

std::string mail_message(const NotifyChannel& c, const std::string& station,
                         const Notification& n) {
    const auto doc = Json::parse(n.body);
    std::string to;
    for (const auto& r : c.to) to += (to.empty() ? "" : ", ") + r;
    char host[256] = "localhost";
    ::gethostname(host, sizeof host - 1);
    std::string m;
    m += "Date: " + mail_date(now_utc()) + "\n";
    m += "From: " + c.from + "\n";
    m += "To: " + to + "\n";
    m += "Subject: " + header_text(n.subject) + "\n";
    m += "Message-ID: <tlsmon." + std::to_string(n.id) + "." + std::to_string(n.created) + "." +
         header_text(station) + "@" + host + ">\n";
    m += "MIME-Version: 1.0\n";
    m += "Content-Type: text/plain; charset=UTF-8\n";
    m += "Content-Transfer-Encoding: 8bit\n";
    m += "X-tlsmon-Notification: " + std::to_string(n.id) + "\n";
    m += "\n" + notification_text(doc);
    return crlf(m);
}

}  // namespace

ChannelSend email_channel(const NotifyChannel& config, const std::string& station) {
    global_init();
    return [c = config, station](const Notification& n) {
        Easy e;
        common_options(e, c);
        const std::string message = mail_message(c, station, n);
        Upload upload{&message};
        const std::string from = "<" + c.from + ">";
        curl_easy_setopt(e.handle, CURLOPT_MAIL_FROM, from.c_str());
        for (const auto& r : c.to) e.list_a = curl_slist_append(e.list_a, ("<" + r + ">").c_str());
        curl_easy_setopt(e.handle, CURLOPT_MAIL_RCPT, e.list_a);
        curl_easy_setopt(e.handle, CURLOPT_USE_SSL,
                         c.starttls == StartTls::required   ? static_cast<long>(CURLUSESSL_ALL)
                         : c.starttls == StartTls::optional ? static_cast<long>(CURLUSESSL_TRY)
                                                            : static_cast<long>(CURLUSESSL_NONE));
        std::string password;
        if (!c.username.empty()) {
            curl_easy_setopt(e.handle, CURLOPT_USERNAME, c.username.c_str());
            if (!c.password_file.empty()) {
                password = read_secret(c.password_file);
                curl_easy_setopt(e.handle, CURLOPT_PASSWORD, password.c_str());
            }
        }
        curl_easy_setopt(e.handle, CURLOPT_READFUNCTION, read_upload);
        curl_easy_setopt(e.handle, CURLOPT_READDATA, &upload);
        curl_easy_setopt(e.handle, CURLOPT_UPLOAD, 1L);
        e.perform("mail to " + c.url);
    };
}

ChannelSend webhook_channel(const NotifyChannel& config) {
    global_init();
    return [c = config](const Notification& n) {
        Easy e;
        common_options(e, c);
        e.list_a = curl_slist_append(e.list_a, "Content-Type: application/json");
        e.list_a =
            curl_slist_append(e.list_a, ("X-tlsmon-Notification: " + std::to_string(n.id)).c_str());
        if (!c.token_file.empty()) {
            e.list_a = curl_slist_append(
                e.list_a, ("Authorization: Bearer " + read_secret(c.token_file)).c_str());
        }
        curl_easy_setopt(e.handle, CURLOPT_HTTPHEADER, e.list_a);
        curl_easy_setopt(e.handle, CURLOPT_POST, 1L);
        curl_easy_setopt(e.handle, CURLOPT_POSTFIELDS, n.body.c_str());
        curl_easy_setopt(e.handle, CURLOPT_POSTFIELDSIZE, static_cast<long>(n.body.size()));
        curl_easy_setopt(e.handle, CURLOPT_USERAGENT, "tlsmon");
        std::string reply;
        curl_easy_setopt(e.handle, CURLOPT_WRITEFUNCTION, keep_reply);
        curl_easy_setopt(e.handle, CURLOPT_WRITEDATA, &reply);
        e.perform("POST to " + c.url);
        long status = 0;
        curl_easy_getinfo(e.handle, CURLINFO_RESPONSE_CODE, &status);
        if (status < 200 || status > 299) {
            while (!reply.empty() && (reply.back() == '\n' || reply.back() == '\r'))
                reply.pop_back();
            throw Error("POST to " + c.url + ": HTTP " + std::to_string(status) +
                        (reply.empty() ? "" : " (" + reply.substr(0, 200) + ")"));
        }
    };
}

}  // namespace tlsmon
