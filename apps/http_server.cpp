#include "http_server.hpp"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http.hpp>
#include <cctype>
#include <list>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

namespace vmas::cli {
namespace {

namespace net = boost::asio;
namespace http = boost::beast::http;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

constexpr auto kNoDeadline = Clock::time_point::max();
constexpr int kAcceptPollMs = 50;  // how often serve() and the watchdog look at stop()
constexpr auto kWatchdogPeriod = std::chrono::milliseconds(kAcceptPollMs);

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// %XX and '+' of a query component.
std::string url_decode(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] == '%' && i + 2 < text.size() &&
               std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
               std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out += static_cast<char>(std::stoi(std::string(text.substr(i + 1, 2)), nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

HttpRequest to_request(const http::request<http::string_body>& message) {
  HttpRequest request;
  request.method = std::string(message.method_string());
  const std::string_view target(message.target().data(), message.target().size());
  const std::size_t question = target.find('?');
  request.path = url_decode(target.substr(0, question));
  if (question != std::string_view::npos) {
    std::string_view query = target.substr(question + 1);
    while (!query.empty()) {
      const std::size_t amp = query.find('&');
      const std::string_view pair = query.substr(0, amp);
      const std::size_t equals = pair.find('=');
      request.query[url_decode(pair.substr(0, equals))] =
          equals == std::string_view::npos ? "" : url_decode(pair.substr(equals + 1));
      query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
    }
  }
  for (const auto& field : message)
    request.headers[lower(std::string(field.name_string()))] = std::string(field.value());
  request.body = message.body();
  return request;
}

}  // namespace

std::string HttpRequest::header(const std::string& name) const {
  const auto found = headers.find(name);
  return found == headers.end() ? "" : found->second;
}

void HttpResponse::json_error(int code, const std::string& message) {
  status = code;
  content_type = "application/json";
  body = nlohmann::json{{"error", message}}.dump(-1, ' ', false,
                                                 nlohmann::json::error_handler_t::replace);
}

// One connection: its socket's descriptor while the socket is open (the watchdog shuts it down
// when its deadline passes or the server stops), and its thread.
struct Connection {
  int descriptor = -1;
  Clock::time_point deadline = kNoDeadline;
  bool shut = false;
  std::atomic<bool> finished{false};
  std::thread thread;
};

struct Route {
  std::string method, path;
  HttpServer::Handler handler;
  bool matches(const HttpRequest& request) const {
    if (request.method != method) return false;
    const std::size_t star = path.size() >= 2 && path.compare(path.size() - 2, 2, "/*") == 0
                                 ? path.size() - 1
                                 : std::string::npos;
    if (star != std::string::npos) return request.path.compare(0, star, path, 0, star) == 0;
    return request.path == path;
  }
};

struct HttpServer::State {
  HttpLimits limits;
  net::io_context io;
  tcp::acceptor acceptor{io};
  Guard guard;
  std::vector<Route> routes;
  std::atomic<bool> stopping{false};
  std::mutex mutex;  // guards connections and their deadlines
  std::list<std::shared_ptr<Connection>> connections;

  void set_deadline(Connection& connection, Clock::time_point deadline) {
    const std::lock_guard<std::mutex> lock(mutex);
    connection.deadline = deadline;
  }

  // Shuts down the sockets whose deadline has passed (all of them once stopping).
  void enforce_deadlines() {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto now = Clock::now();
    for (const auto& connection : connections)
      if (!connection->shut && connection->descriptor >= 0 &&
          (stopping || now > connection->deadline)) {
        ::shutdown(connection->descriptor, SHUT_RDWR);
        connection->shut = true;
      }
  }

  void respond(const HttpRequest& request, HttpResponse& response) {
    for (const Route& route : routes)
      if (route.matches(request)) {
        try {
          route.handler(request, response);
        } catch (const std::exception& e) {
          response = HttpResponse();
          response.json_error(500, e.what());
        }
        return;
      }
    response.json_error(404, "no such page: " + request.path);
  }

  // Writes a response whole (header and body in one gathered write).
  bool write(tcp::socket& socket, Connection& connection, HttpResponse& response, bool keep_alive) {
    http::response<http::string_body> message{static_cast<http::status>(response.status), 11};
    message.set(http::field::content_type, response.content_type);
    for (const auto& [name, value] : response.headers) message.set(name, value);
    message.body() = std::move(response.body);
    message.keep_alive(keep_alive);
    message.prepare_payload();
    set_deadline(connection, Clock::now() + limits.write_time);
    boost::system::error_code error;
    http::write(socket, message, error);
    return !error;
  }

  // Whether the client of a stream has closed its side (it sends nothing after the request): a
  // write would only find out at the second one after the close. Looked at between calls of
  // `next`, which therefore must not wait long.
  static bool peer_gone(tcp::socket& socket) {
    pollfd p{socket.native_handle(), POLLIN | POLLRDHUP, 0};
    return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
  }

  // A stream: the header, then chunks as `next` makes them, each written under the deadline.
  void write_stream(tcp::socket& socket, Connection& connection, HttpResponse& response) {
    http::response<http::empty_body> head{static_cast<http::status>(response.status), 11};
    head.set(http::field::content_type, response.content_type);
    for (const auto& [name, value] : response.headers) head.set(name, value);
    head.chunked(true);
    head.keep_alive(false);
    http::response_serializer<http::empty_body> serializer{head};
    boost::system::error_code error;
    set_deadline(connection, Clock::now() + limits.write_time);
    http::write_header(socket, serializer, error);
    std::string chunk;
    while (!error && !stopping && !peer_gone(socket)) {
      set_deadline(connection, kNoDeadline);  // `next` may wait for news
      chunk.clear();
      if (!response.next(chunk) || stopping) break;
      if (chunk.empty()) continue;
      set_deadline(connection, Clock::now() + limits.write_time);
      net::write(socket, http::make_chunk(net::buffer(chunk)), error);
    }
    if (!error) {
      set_deadline(connection, Clock::now() + limits.write_time);
      net::write(socket, http::make_chunk_last(), error);
    }
    if (response.done) response.done();
  }

  void serve_connection(tcp::socket socket, const std::shared_ptr<Connection>& connection) {
    boost::beast::flat_buffer buffer;
    for (bool open = true; open && !stopping;) {
      set_deadline(*connection, Clock::now() + limits.request_time);
      http::request_parser<http::string_body> parser;
      parser.header_limit(static_cast<std::uint32_t>(limits.header_bytes));
      parser.body_limit(limits.body_bytes);
      boost::system::error_code error;
      HttpResponse response;
      // The guard sees the header before the body is read: a client it refuses never makes the
      // server hold a body (their limit grows with the input: a density file by input point).
      http::read_header(socket, buffer, parser, error);
      if (!error && guard && !guard(to_request(parser.get()), response)) {
        write(socket, *connection, response, false);
        break;
      }
      if (!error && !parser.is_done()) http::read(socket, buffer, parser, error);
      if (error == http::error::body_limit) {
        response.json_error(413,
                            "request body over " + std::to_string(limits.body_bytes) + " bytes");
        write(socket, *connection, response, false);
        break;
      }
      if (error == http::error::header_limit) {
        response.json_error(
            431, "request header over " + std::to_string(limits.header_bytes) + " bytes");
        write(socket, *connection, response, false);
        break;
      }
      if (error) break;  // closed, timed out, stopped, or not HTTP
      const HttpRequest request = to_request(parser.get());
      respond(request, response);
      if (response.next) {
        write_stream(socket, *connection, response);
        break;
      }
      const bool keep_alive = parser.get().keep_alive() && !response.close;
      open = write(socket, *connection, response, keep_alive) && keep_alive;
    }
    {
      // Out of the watchdog's sight before the descriptor is released (and maybe reused).
      const std::lock_guard<std::mutex> lock(mutex);
      connection->descriptor = -1;
    }
    boost::system::error_code ignored;
    socket.shutdown(tcp::socket::shutdown_both, ignored);
    socket.close(ignored);
    connection->finished = true;
  }

  // Joins the threads of the connections that have ended (all of them with `all`).
  void reap(bool all) {
    std::list<std::shared_ptr<Connection>> ended;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      for (auto it = connections.begin(); it != connections.end();) {
        if (all || (*it)->finished) {
          ended.push_back(*it);
          it = connections.erase(it);
        } else {
          ++it;
        }
      }
    }
    for (const auto& connection : ended) connection->thread.join();
  }
};

HttpServer::HttpServer(HttpLimits limits) : state_(std::make_shared<State>()) {
  state_->limits = limits;
}

HttpServer::~HttpServer() {
  stop();
  state_->reap(true);
}

int HttpServer::bind(const std::string& host, int port) {
  boost::system::error_code error;
  tcp::resolver resolver(state_->io);
  const auto endpoints =
      resolver.resolve(host, std::to_string(port), tcp::resolver::numeric_service, error);
  if (error || endpoints.empty())
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " +
                             (error ? error.message() : "no address"));
  const tcp::endpoint endpoint = *endpoints.begin();
  tcp::acceptor& acceptor = state_->acceptor;
  acceptor.open(endpoint.protocol(), error);
  if (!error) acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (!error) acceptor.bind(endpoint, error);
  if (!error) acceptor.listen(net::socket_base::max_listen_connections, error);
  if (error)
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " +
                             error.message());
  return acceptor.local_endpoint().port();
}

void HttpServer::set_guard(Guard guard) { state_->guard = std::move(guard); }

void HttpServer::route(const std::string& method, const std::string& path, Handler handler) {
  state_->routes.push_back({method, path, std::move(handler)});
}

void HttpServer::serve() {
  State& state = *state_;
  std::thread watchdog([&state] {
    while (!state.stopping) {
      std::this_thread::sleep_for(kWatchdogPeriod);
      state.enforce_deadlines();
    }
    state.enforce_deadlines();
  });
  while (!state.stopping) {
    pollfd listening{state.acceptor.native_handle(), POLLIN, 0};
    const int ready = ::poll(&listening, 1, kAcceptPollMs);
    state.reap(false);
    if (ready <= 0 || state.stopping) continue;
    boost::system::error_code error;
    tcp::socket socket(state.io);
    state.acceptor.accept(socket, error);
    if (error) continue;
    socket.set_option(tcp::no_delay(true), error);
    std::size_t open;
    {
      const std::lock_guard<std::mutex> lock(state.mutex);
      open = state.connections.size();
    }
    if (open >= state.limits.connections) {
      // The kernel's buffer takes this small reply at once.
      HttpResponse busy;
      busy.json_error(503, "too many connections");
      Connection none;
      state.write(socket, none, busy, false);
      continue;
    }
    auto connection = std::make_shared<Connection>();
    connection->descriptor = socket.native_handle();
    {
      const std::lock_guard<std::mutex> lock(state.mutex);
      state.connections.push_back(connection);
    }
    connection->thread = std::thread(
        [&state, connection](tcp::socket s) { state.serve_connection(std::move(s), connection); },
        std::move(socket));
  }
  watchdog.join();
  boost::system::error_code ignored;
  state.acceptor.close(ignored);
  state.reap(true);
}

void HttpServer::stop() { state_->stopping = true; }

bool HttpServer::stopping() const { return state_->stopping; }

}  // namespace vmas::cli
