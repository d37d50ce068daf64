#pragma once
/// `sscs lsp`: a Language Server Protocol 3.17 server over the files an editor has open. It
/// takes JSON-RPC messages (the framing is the caller's: cli/lsp.cpp reads stdio) and sends
/// responses and notifications through `send`. Files are compiled and checked on a worker
/// thread from the editor's buffers, so the server answers while a check runs (or never ends);
/// the last change wins. It never writes a file.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "lsp/analysis.h"

namespace sscs::lsp {

/// JSON-RPC's error code for a message that cannot be read (the framing's: cli/lsp.cpp).
constexpr int kParseError = -32700;

struct ServerOptions {
  CompileOptions compile;
  /// Called (on the worker) with every project root the open files have, before a file of a new
  /// one is compiled: what files named inside input files may read (the CLI confines reads there).
  std::function<void(const std::vector<std::string>& roots)> confine;
  /// false: every change is compiled before handle() returns (the unit tests).
  bool threaded = true;
};

class Server {
 public:
  using Send = std::function<void(const nlohmann::json&)>;
  Server(Send send, ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Handles one message: a request (answered through `send`), a notification, or a response.
  /// Returns false once `exit` came.
  bool handle(const nlohmann::json& message);
  /// 0 when `shutdown` came before `exit`, else 1 (LSP 3.17).
  int exit_code() const { return shutdown_ ? 0 : 1; }
  /// Waits until every compile asked for has been published.
  void settle();

 private:
  struct Doc {
    std::string uri;
    std::string text;
    FileKind kind = FileKind::Other;
    long version = -1;
  };
  nlohmann::json request(const std::string& method, const nlohmann::json& params);
  void notification(const std::string& method, const nlohmann::json& params);
  void changed(const std::string& path);  ///< queue the file and the open files that read it
  void work();                            ///< the worker: compile what is queued, newest text
  void compile_one(const std::string& path);
  void publish(const std::string& root, std::map<std::string, std::vector<Problem>> found);
  std::shared_ptr<const Analysis> analysis_of(const std::string& path) const;
  nlohmann::json hover(const Doc& doc, int line, int character) const;
  nlohmann::json definition(const Doc& doc, int line, int character) const;
  nlohmann::json completion(const Doc& doc, int line, int character) const;
  nlohmann::json symbols(const Doc& doc) const;
  void send(const nlohmann::json& message);

  Send send_;
  ServerOptions options_;
  bool initialized_ = false, shutdown_ = false, utf8_ = false;
  std::map<std::string, Doc> docs_;  ///< open files by absolute path (the main thread's)

  mutable std::mutex m_;  ///< guards what follows, shared with the worker
  std::condition_variable cv_;
  std::shared_ptr<const Sources::Unsaved> unsaved_ = std::make_shared<Sources::Unsaved>();
  std::map<std::string, FileKind> open_;  ///< the open files the worker may compile
  std::set<std::string> pending_;
  bool busy_ = false, stop_ = false;
  std::string compiling_;  ///< the file the worker compiles now
  std::atomic<bool> cancel_{false};  ///< set when an edit makes that compile's result stale
  std::map<std::string, std::shared_ptr<const Analysis>> analyses_;  ///< the last of each open file
  /// The last that compiled: hover, definition and completion read it while the buffer is half typed.
  std::map<std::string, std::shared_ptr<const Analysis>> good_;
  /// What each compiled file published, by the file it is in: a file's diagnostics are the union.
  std::map<std::string, std::map<std::string, std::vector<Problem>>> published_;
  std::map<std::string, long> versions_;           ///< each open file's version, as the worker takes it
  std::map<std::string, long> published_version_;  ///< the version each file's last analysis was of
  std::map<std::string, LibraryCache> libraries_;  ///< each open vault's kept library (the worker's)
  std::mutex send_m_;
  std::thread worker_;
};

/// `file:///a%20b/c.yaml` -> `/a b/c.yaml`; "" for another scheme.
std::string uri_to_path(const std::string& uri);
/// `/a b/c.yaml` -> `file:///a%20b/c.yaml`.
std::string path_to_uri(const std::string& path);

}  // namespace sscs::lsp
