#include "config/config_loader.hpp"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

namespace df::config {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

class Collector : public google::protobuf::io::ErrorCollector {
  public:
    explicit Collector(std::string where) : where_(std::move(where)) {}
    void AddError(int line, google::protobuf::io::ColumnNumber column,
                  const std::string& message) override {
        if (!errors_.empty()) errors_ += "; ";
        errors_ += where_ + ":" + std::to_string(line + 1) + ":" + std::to_string(column + 1) +
                   ": " + message;
    }
    const std::string& errors() const { return errors_; }

  private:
    std::string where_;
    std::string errors_;
};

Status merge(const std::string& text, const std::string& where, Message* message) {
    Collector collector(where);
    google::protobuf::TextFormat::Parser parser;
    parser.RecordErrorsTo(&collector);
    // Each text is parsed on its own first: within one file or --set a field given twice is an
    // error (merging would keep the last silently); across them the later one wins.
    std::unique_ptr<Message> alone(message->New());
    if (!parser.ParseFromString(text, alone.get())) {
        return Status(StatusCode::kInvalidArgument,
                      "bad configuration (" + message->GetTypeName() + "): " + collector.errors());
    }
    message->MergeFrom(*alone);
    return Status::ok();
}

void describe_into(const Message& m, const std::string& prefix, std::ostringstream& out) {
    const auto* desc = m.GetDescriptor();
    const Reflection* refl = m.GetReflection();
    for (int i = 0; i < desc->field_count(); ++i) {
        const FieldDescriptor* f = desc->field(i);
        const std::string name = prefix + f->name();
        if (f->is_repeated()) {
            out << name << ": [";
            for (int k = 0; k < refl->FieldSize(m, f); ++k) {
                std::string v;
                google::protobuf::TextFormat::PrintFieldValueToString(m, f, k, &v);
                out << (k ? ", " : "") << v;
            }
            out << "]\n";
        } else if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
            describe_into(refl->GetMessage(m, f), name + ".", out);
        } else {
            std::string v;
            google::protobuf::TextFormat::PrintFieldValueToString(m, f, -1, &v);
            out << name << ": " << v << (refl->HasField(m, f) ? "" : " (default)") << "\n";
        }
    }
}

}  // namespace

Status load(const std::string& path, const std::vector<std::string>& overrides, Message* message) {
    if (!path.empty()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            return Status(StatusCode::kNotFound,
                          "configuration file '" + path + "' does not exist");
        }
        if (!std::filesystem::is_regular_file(path, ec)) {
            return Status(StatusCode::kInvalidArgument,
                          "configuration file '" + path +
                              "' is not a regular file (a folder?); expected a protobuf text file");
        }
        std::ifstream in(path);
        if (!in) {
            return Status(StatusCode::kNotFound, "cannot read configuration file '" + path + "'");
        }
        std::stringstream text;
        text << in.rdbuf();
        if (in.bad()) {
            return Status(StatusCode::kIoError,
                          "error while reading configuration file '" + path + "'");
        }
        DF_RETURN_IF_ERROR(merge(text.str(), path, message));
    }
    for (const auto& o : overrides) {
        DF_RETURN_IF_ERROR(merge(o, "--set '" + o + "'", message));
    }
    return Status::ok();
}

std::string describe(const Message& message) {
    std::ostringstream out;
    describe_into(message, "", out);
    return out.str();
}

}  // namespace df::config
