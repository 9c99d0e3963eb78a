// SPDX-License-Identifier: Apache-2.0
// `lasmesh view`'s request checks and the command line it shows, case by case (the browser test
// drives the server itself: tests/cli/view_test.sh).
#include "cli/command_line.hpp"
#include "cli/request_checks.hpp"

#include <doctest/doctest.h>

#include <set>

using namespace lasmesh::cli;

TEST_CASE("view: the Host header must name this server on its port") {
    const std::string machine = "deckhand";
    struct Case {
        const char* host;
        bool local, shared; // accepted listening on 127.0.0.1; on the network
    };
    const Case cases[] = {
        {"127.0.0.1:8080", true, true},
        {"localhost:8080", true, true},
        {"[::1]:8080", true, true},
        {"127.0.0.1:8081", false, false}, // another port
        {"127.0.0.1", false, false},
        {"127.0.0.1:", false, false}, // no port
        {"127.0.0.1:08080", false, false},
        {":8080", false, false},
        {"", false, false},
        {"evil.example:8080", false, false}, // DNS rebinding
        {"localhost.evil.example:8080", false, false},
        {"192.168.1.5:8080", false, true},
        {"[fe80::1]:8080", false, true}, // addresses: shared only
        {"deckhand:8080", false, true},
        {"deckhand.example:8080", false, false},
        {"[::1:8080", false, false},
        {"[evil]:8080", false, false},
    };
    for (const Case& c : cases) {
        CAPTURE(c.host);
        CHECK(host_names_server(c.host, 8080, false, machine) == c.local);
        CHECK(host_names_server(c.host, 8080, true, machine) == c.shared);
    }
    CHECK(!host_names_server("deckhand:8080", 8080, true, "")); // no name known: names refused
}

TEST_CASE("view: tokens are 128 random bits, compared whole") {
    std::set<std::string> tokens;
    for (int i = 0; i < 100; ++i) {
        const std::string token = random_token();
        CHECK(token.size() == 32);
        CHECK(token.find_first_not_of("0123456789abcdef") == std::string::npos);
        tokens.insert(token);
    }
    CHECK(tokens.size() == 100);
    const std::string token = random_token();
    CHECK(same_token(token, token));
    CHECK(!same_token(token.substr(0, 31), token));
    CHECK(!same_token(token + "0", token));
    CHECK(!same_token("", token));
    std::string other = token;
    other[31] = other[31] == '0' ? '1' : '0';
    CHECK(!same_token(other, token));
}

TEST_CASE("view: the command line shown, quoted for a shell, only what differs from the defaults") {
    CHECK(shell_word("deck.las") == "deck.las");
    CHECK(shell_word("/data/site-1/deck_2,a%b+c=d@e:f") == "/data/site-1/deck_2,a%b+c=d@e:f");
    CHECK(shell_word("my deck.las") == "'my deck.las'");
    CHECK(shell_word("it's.las") == "'it'\\''s.las'");
    CHECK(shell_word("$HOME/x;rm -rf") == "'$HOME/x;rm -rf'");
    CHECK(shell_word("") == "''");

    MeshOptions o;
    o.inputs = {"deck.las"};
    o.outputs = {"deck.ply"};
    CHECK(command_line(o) == "lasmesh deck.las -o deck.ply");
    o.inputs = {"a b.las", "c.laz"};
    o.outputs = {"x.ply", "x.html"};
    o.grid.voxel = 0.05;
    o.iso = "3";
    o.surface = "closed";
    o.placement = "iso";
    o.simplify = "0.2cell";
    o.min_piece = "0";
    o.no_normals = true;
    o.glb_compression = "draco";
    o.draco.level = 10;
    o.crs = "EPSG:32631";
    CHECK(command_line(o) == "lasmesh 'a b.las' c.laz -o x.ply -o x.html --crs EPSG:32631 --voxel 0.05 --iso 3 "
                             "--surface closed --placement iso --min-piece 0 --simplify 0.2cell --no-normals "
                             "--glb-compression draco --draco-level 10");
}
