// Every server of a railvib node on the address the user asked for.
//
// roscpp binds its TCPROS server to loopback when ROS_IP / ROS_HOSTNAME name a loopback address,
// but its XML-RPC server (xmlrpcpp, XmlRpcSocket::bind in ros_comm 1.15) always binds the wildcard
// address: with ROS_IP=127.0.0.1 a C++ node still listens on every interface, and roscpp has no
// option to change it. This bind(), linked into each node executable (and exported, so it
// interposes on the C library's for the ROS libraries too), turns a wildcard bind into a loopback
// bind when ROS_HOSTNAME, else ROS_IP (the order roscpp reads them), is a loopback name or
// address; any other bind goes to the kernel unchanged. It is plain ELF symbol interposition of
// the executable, not LD_PRELOAD.
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace {

bool loopbackRequested() {
  for (const char* var : {"ROS_HOSTNAME", "ROS_IP"}) {
    const char* value = std::getenv(var);
    if (value == nullptr || *value == '\0') continue;
    const std::string v(value);
    return v == "localhost" || v.rfind("127.", 0) == 0 || v == "::1" || v == "ip6-localhost";
  }
  return false;
}

int kernelBind(int fd, const struct sockaddr* address, socklen_t length) {
  return static_cast<int>(::syscall(SYS_bind, fd, address, length));
}

}  // namespace

extern "C" int bind(int fd, const struct sockaddr* address, socklen_t length) {
  if (address != nullptr && loopbackRequested()) {
    if (address->sa_family == AF_INET && length >= sizeof(sockaddr_in)) {
      sockaddr_in a;
      std::memcpy(&a, address, sizeof a);
      if (a.sin_addr.s_addr == htonl(INADDR_ANY)) {
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        return kernelBind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
      }
    } else if (address->sa_family == AF_INET6 && length >= sizeof(sockaddr_in6)) {
      sockaddr_in6 a;
      std::memcpy(&a, address, sizeof a);
      if (IN6_IS_ADDR_UNSPECIFIED(&a.sin6_addr)) {
        a.sin6_addr = in6addr_loopback;
        return kernelBind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a);
      }
    }
  }
  return kernelBind(fd, address, length);
}
