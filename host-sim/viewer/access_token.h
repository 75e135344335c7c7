// The viewer's token. A viewer that listens beyond loopback is a remote
// control for every robot its node serves, to anyone who can reach its
// port: it then asks every request for a random token, printed with its URL
// (`http://HOST:PORT/?token=...`). The first request carries it in the
// query; the answer sets it as a cookie (HttpOnly, SameSite=Strict), which
// the browser sends with the page's files and its WebSocket, so the page
// itself needs no change.
#pragma once

#include <string>
#include <string_view>

namespace troupe::viewer {

/// The cookie that carries the token.
inline constexpr std::string_view kTokenCookie = "troupe_view_token";

/// 32 hex digits from the kernel's random source (128 bits: not guessable
/// over a network).
std::string make_token();

/// The token a request presents: its target's `token=` query parameter,
/// else the cookie's value in its Cookie header; empty when neither.
std::string presented_token(std::string_view target, std::string_view cookie_header);

/// Whether `presented` is `token`, in time that does not depend on where
/// they differ.
bool token_matches(std::string_view presented, std::string_view token);

}  // namespace troupe::viewer
