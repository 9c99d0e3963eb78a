// SPDX-License-Identifier: Apache-2.0
// man_page: roff (man(7) macros) from the command line's declarations, plus the sections no
// option carries: what lasmesh does, its output, its exit status.
#include "man_page.hpp"

#include "help_format.hpp"

#include <sstream>

namespace lasmesh::cli {

namespace {

// Text as roff reads it literally: backslashes and hyphens escaped, no line starting a request.
std::string roff(const std::string& text) {
    std::string out;
    bool line_start = true;
    for (char c : text) {
        if (line_start && (c == '.' || c == '\'')) out += "\\&";
        if (c == '\\')
            out += "\\e";
        else if (c == '-')
            out += "\\-";
        else
            out += c;
        line_start = c == '\n';
    }
    return out;
}

void options_section(std::ostringstream& out, const CLI::App& app) {
    for (const CLI::Option* option : app.get_options()) {
        if (option->get_group().empty() || option->get_positional()) continue; // hidden, or the INPUT
        std::string names = option->get_name(false, true);                     // "-o,--output"
        for (std::size_t comma = names.find(','); comma != std::string::npos; comma = names.find(',', comma + 2))
            names.replace(comma, 1, ", ");
        out << ".TP\n\\fB" << roff(names) << "\\fR";
        if (const std::string value = value_text(*option); !value.empty()) out << " \\fI" << roff(value) << "\\fR";
        out << "\n" << roff(description_text(*option)) << "\n";
    }
}

// A footer's lines, kept as they are (examples are aligned by hand).
void literal(std::ostringstream& out, const std::string& text) {
    out << ".nf\n" << roff(text) << "\n.fi\n";
}

} // namespace

std::string man_page(const CLI::App& app, const std::string& version) {
    std::ostringstream out;
    out << ".TH LASMESH 1 \"\" \"lasmesh " << roff(version) << "\" \"User Commands\"\n"
        << ".SH NAME\nlasmesh \\- LAS and LAZ point clouds to small coloured triangle meshes\n"
        << ".SH SYNOPSIS\n.B lasmesh\n.I INPUT...\n.B \\-o\n.I "
           "OUT.ply|OUT.drc|OUT.glb|OUT.png|OUT.html|SITE/TILESET.json\n[\\fIOPTIONS\\fR]\n.br\n";
    for (const CLI::App* command : app.get_subcommands({}))
        out << ".B lasmesh " << roff(command->get_name()) << "\n[\\fIOPTIONS\\fR] ...\n.br\n";
    out << ".SH DESCRIPTION\n"
        << roff("lasmesh reads LAS or LAZ point clouds (files, one survey of many files, or - for standard input; "
                "gzip, bzip2, xz and "
                "zstd streams are recognised by their first bytes), counts the points into a sparse grid of "
                "cubic cells on an OpenCL device (PoCL on the CPU, or any GPU), extracts one sheet through "
                "the points of each surface (or a closed surface) by marching cubes, removes small isolated "
                "pieces, simplifies the mesh to an error bound and writes it with per-vertex colour and normals "
                "as PLY, Draco (.drc) or glTF 2.0 binary (.glb: plain by default, Draco with "
                "--glb-compression draco), all outputs from one pass, all of them or none. A .json output is an "
                "OGC 3D Tiles 1.1 tileset: levels of detail from coarser grids, cut into .glb tiles on one "
                "lattice, placed on the globe through the survey's coordinate system. A .html output is one page that "
                "shows the mesh in a web browser, offline, to look at, cut and measure.")
        << "\n.PP\n"
        << roff("Output positions are single precision and relative to a local origin, so centimetres survive "
                "at projected coordinates: the PLY header's comment origin X Y Z, the Draco metadata "
                "origin_x, origin_y, origin_z, and the glTF extras (with --glb-origin node also a node "
                "translation).")
        << "\n.SH OPTIONS\n";
    options_section(out, app);
    out << ".SH COMMANDS\n";
    for (const CLI::App* command : app.get_subcommands({})) {
        out << ".SS \"lasmesh " << roff(command->get_name()) << "\"\n" << roff(command->get_description()) << "\n";
        options_section(out, *command);
        if (!command->get_footer().empty()) {
            out << ".PP\n";
            literal(out, command->get_footer());
        }
    }
    out << ".SH EXIT STATUS\n"
        << ".TP\n.B 0\nSuccess.\n"
        << ".TP\n.B 1\nUsage: a bad option or value; nothing was read.\n"
        << ".TP\n.B 2\nBad input: the message names the file, the byte offset or record, and what was expected; "
           "nothing is written.\n"
        << ".TP\n.B 3\nThe OpenCL device: none found, or it failed.\n"
        << ".TP\n.B 4\nAn output could not be written; no output is left half-written.\n"
        << ".TP\n.B 5\nAn internal error, or the system refused memory.\n"
        << ".SH EXAMPLES\n";
    const std::string footer = app.get_footer(); // the examples, then a blank line and the exit codes
    literal(out, footer.substr(0, footer.find("\n\n")));
    out << ".SH SEE ALSO\n.BR pdal (1),\n.BR draco_decoder (1)\n";
    return out.str();
}

} // namespace lasmesh::cli
