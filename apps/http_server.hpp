#pragma once
// The small HTTP/1.1 server of `vmas edit` (Boost.Beast over blocking sockets): one thread per
// connection, every read and write under a deadline that a watchdog enforces by shutting the
// socket down, so that slow or hostile clients hold a thread each but never the server, and
// stop() ends every connection at once.
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace vmas::cli {

struct HttpRequest {
  std::string method;                          // "GET", "POST", ...
  std::string path;                            // the target without its query
  std::map<std::string, std::string> query;    // decoded parameters of the query
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;

  // A header's value, or "" (name in lower case).
  std::string header(const std::string& name) const;
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  // A stream (server-sent events): after the header, `next(chunk)` is called again and again
  // and each chunk written (an empty one: nothing), until it returns false or the client or the
  // server goes; then `done()`. Between calls the server looks whether the client has hung up
  // or stop() came, so `next` should wait for news briefly (tens of ms), not for long.
  // The connection closes afterwards.
  std::function<bool(std::string& chunk)> next;
  std::function<void()> done;
  bool close = false;  // close the connection after this response

  void json_error(int status, const std::string& message);  // {"error": message}
};

struct HttpLimits {
  std::size_t header_bytes = 8 * 1024;
  std::size_t body_bytes = 64 * 1024;
  // A request must have arrived whole (header and body) this long after the server began to
  // wait for it, also on a kept-alive connection; otherwise the connection is closed.
  std::chrono::milliseconds request_time{10'000};
  // Each response (each chunk of a stream) must have been written within this.
  std::chrono::milliseconds write_time{10'000};
  std::size_t connections = 256;  // open at once; more are answered 503 and closed
};

class HttpServer {
 public:
  // Decides before routing: returns false after filling the response (sent, then the
  // connection is closed), true to go on to the handler.
  using Guard = std::function<bool(const HttpRequest&, HttpResponse&)>;
  using Handler = std::function<void(const HttpRequest&, HttpResponse&)>;

  explicit HttpServer(HttpLimits limits = {});
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Listens on host:port (0: any free port); returns the port. Throws std::runtime_error.
  int bind(const std::string& host, int port);
  void set_guard(Guard guard);
  // Requests for exactly `path` (or, when it ends with "/*", any path under it) with `method`.
  void route(const std::string& method, const std::string& path, Handler handler);

  // Serves until stop(); returns once every connection has ended.
  void serve();
  // From any thread: closes every connection and makes serve() return (within ~0.2 s, whatever
  // the clients do). Streams see stopping() and end.
  void stop();
  bool stopping() const;

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace vmas::cli
