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

/// Reads one message's body from stdin: "" at the end of the input. A malformed header is skipped
/// to the next blank line, and its body read as said, so one bad message does not end the session.
std::optional<std::string> read_message(std::istream& in, std::string& problem) {
  std::string line;
  long long length = -1;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {
      if (length < 0) {
        problem = "a message without Content-Length";
        return std::string();
      }
      if (static_cast<size_t>(length) > kMostMessageBytes) {
        problem = fmt::format("a message of {} bytes, above the {} MB a message may have", length, kMostMessageBytes >> 20);
        in.ignore(length);
        return std::string();
      }
      std::string body(static_cast<size_t>(length), '\0');
      in.read(body.data(), length);
      if (in.gcount() != length) return std::nullopt;
      return body;
    }
    constexpr std::string_view header = "content-length:";
    if (line.size() > header.size() && std::equal(header.begin(), header.end(), line.begin(), [](char a, char b) { return a == std::tolower(b); })) {
      char* end = nullptr;
      length = std::strtoll(line.c_str() + header.size(), &end, 10);
    }
  }
  return std::nullopt;
}

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
  while (true) {
    std::string problem;
    std::optional<std::string> body = read_message(std::cin, problem);
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
