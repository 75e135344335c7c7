// troupe keygen NAME: a key pair for secure sessions.
#include <cstdio>

#include "wire/cli/cli.h"
#include "wire/noise/key_file.h"

namespace troupe::cli {

int cmd_keygen(const std::vector<std::string>& args) {
  std::string name;
  auto app = make_app("troupe keygen",
                      {"troupe keygen NAME",
                       "Writes a key pair for secure sessions (wire/README.md, \"Secure sessions\"):\n"
                       "NAME holds the secret key (readable by you only), NAME.pub the public key\n"
                       "to give the other side: a node's config lists its clients' .pub files in\n"
                       "\"clients\"; a client names the node's with --node-key. Existing files are\n"
                       "never overwritten.\n",
                       {"troupe keygen robot7", "troupe keygen laptop && troupe ls robot7.local --identity laptop "
                                                "--node-key robot7.pub"}});
  app->add_option("NAME", name, "the secret key file; the public one is NAME.pub")->required();
  if (int rc = parse(*app, args); rc >= 0) return rc;
  std::string error;
  const size_t slash = name.rfind('/');
  if (!wire::noise::write_key_pair(name, slash == std::string::npos ? name : name.substr(slash + 1), error)) {
    return fail(error);
  }
  wire::noise::Key key;
  if (!wire::noise::read_public_key(name + ".pub", key, error)) return fail(error);
  printf("%s: secret key (keep it here)\n%s.pub: public key %s\n", name.c_str(), name.c_str(),
         wire::noise::key_hex(key).c_str());
  return 0;
}

}  // namespace troupe::cli
