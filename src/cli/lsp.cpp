// `sscs lsp`: the editor server on stdin and stdout (LSP's base protocol: a Content-Length header,
// a blank line, a JSON-RPC message). lsp/server.h answers; this file only frames the messages.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "cli/subcommands.h"
#include "lsp/server.h"

namespace sscs::cli {

namespace {

constexpr size_t kMostMessageBytes = size_t(1) << 30;  ///< a message's body at most (an editor's buffer of 50 MB is well inside)

/// Reads messages from stdin: "" at the end of the input. A header block without a readable
/// Content-Length leaves no way to know where its body ends: the reader says so (`problem`) and
/// skips to the next `Content-Length:`, so one bad message does not deafen the session.
class MessageReader {
 public:
  explicit MessageReader(std::istream& in) : in_(in) {}

  std::optional<std::string> next(std::string& problem) {
    std::string line;
    long long length = -1;
    while (read_line(line)) {
      if (line.empty()) {
        if (length < 0) {
          problem = "a message without a readable Content-Length header (skipped to the next one)";
          if (!resync()) return std::nullopt;
          return std::string();
        }
        if (static_cast<size_t>(length) > kMostMessageBytes) {
          problem = fmt::format("a message of {} bytes, above the {} MB a message may have", length, kMostMessageBytes >> 20);
          in_.ignore(length);
          return std::string();
        }
        std::string body(static_cast<size_t>(length), '\0');
        in_.read(body.data(), length);
        if (in_.gcount() != length) return std::nullopt;
        return body;
      }
      constexpr std::string_view header = "content-length:";
      if (line.size() > header.size() && std::equal(header.begin(), header.end(), line.begin(), [](char a, char b) { return a == std::tolower(b); })) {
        char* end = nullptr;
        const long long n = std::strtoll(line.c_str() + header.size(), &end, 10);
        length = end != line.c_str() + header.size() && n >= 0 ? n : -1;
      }
    }
    return std::nullopt;
  }

 private:
  bool read_line(std::string& line) {
    if (!std::getline(in_, line)) return false;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    line = carry_ + line;
    carry_.clear();
    return true;
  }
  /// Skips input up to the next "Content-Length:" (any case), which the next line read starts with.
  bool resync() {
    constexpr std::string_view header = "content-length:";
    size_t matched = 0;
    char c;
    while (in_.get(c)) {
      matched = std::tolower(static_cast<unsigned char>(c)) == header[matched] ? matched + 1
                : std::tolower(static_cast<unsigned char>(c)) == header[0] ? 1 : 0;
      if (matched == header.size()) {
        carry_ = "Content-Length:";
        return true;
      }
    }
    return false;
  }

  std::istream& in_;
  std::string carry_;
};

}  // namespace

int run_lsp(const Common& common) {
  CompileOptions options;
  if (!common.apply(options, {})) return kInputError;
  std::ios::sync_with_stdio(false);
  // Messages go out whole, one at a time (the worker publishes while the main thread answers).
  auto write = [](const nlohmann::json& message) {
    const std::string body = message.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    const std::string head = fmt::format("Content-Length: {}\r\n\r\n", body.size());
    std::fwrite(head.data(), 1, head.size(), stdout);
    std::fwrite(body.data(), 1, body.size(), stdout);
    std::fflush(stdout);
  };
  lsp::ServerOptions server_options;
  server_options.compile = options;
  server_options.confine = [&common](const std::vector<std::string>& projects) { common.confine_to_projects(projects); };
  lsp::Server server(write, server_options);
  int code = 1;  // the input ended without `exit`
  MessageReader reader(std::cin);
  while (true) {
    std::string problem;
    std::optional<std::string> body = reader.next(problem);
    if (!body) break;
    if (!problem.empty()) {
      write({{"jsonrpc", "2.0"}, {"id", nullptr}, {"error", {{"code", lsp::kParseError}, {"message", problem}}}});
      continue;
    }
    nlohmann::json message = nlohmann::json::parse(*body, nullptr, false);
    if (message.is_discarded()) {
      write({{"jsonrpc", "2.0"}, {"id", nullptr}, {"error", {{"code", lsp::kParseError}, {"message", "a message that is no JSON"}}}});
      continue;
    }
    if (!server.handle(message)) {
      code = server.exit_code();
      break;
    }
  }
  // A compile still running (one that never ends) must not hold the exit: leave at once.
  std::fflush(stdout);
  std::_Exit(code);
}

}  // namespace sscs::cli
