#include "scene/study/StudyResults.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/Plot.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace masse::scene
{
namespace
{
namespace fs = std::filesystem;

std::string cellText(const nlohmann::json& value)
{
    return value.is_null() ? "" : valueText(value);
}

/// A name usable in a file name.
std::string fileWord(const std::string& name)
{
    std::string word;
    for (char c : name)
    {
        word += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
    }
    return word;
}

/// A string for a gnuplot single-quoted literal.
std::string gnuplotText(const std::string& text)
{
    std::string quoted;
    for (char c : text)
    {
        quoted += c == '\'' ? std::string("''") : std::string(1, c);
    }
    return quoted;
}

bool allNumbers(const StudyResults& results, std::size_t parameter)
{
    return std::all_of(results.record.cases.begin(), results.record.cases.end(),
                       [&](const std::vector<nlohmann::json>& values) { return values[parameter].is_number(); });
}
} // namespace

StudyResults collectResults(const std::string& dir)
{
    StudyResults results;
    results.record = readStudyRecord(dir);
    for (std::size_t i = 0; i < results.record.cases.size(); ++i)
    {
        CollectedCase c;
        c.index = i;
        c.values = results.record.cases[i];
        c.outputs.assign(results.record.outputs.size(), nullptr);
        const std::string folder = caseFolder(dir, i);
        const CaseStatus status = readCaseStatus(folder);
        c.exitCode = status.exitCode;
        if (!status.finished)
        {
            c.status = "not run";
            ++results.notRun;
        }
        else if (status.exitCode != 0)
        {
            c.status = "failed";
            c.message = lastLogLine(folder);
            ++results.failed;
        }
        else
        {
            // A pipe or a device in the summary's place would block the collection or read for ever.
            nlohmann::json summary = nlohmann::json::value_t::discarded;
            if (isRegularFile(folder + "/summary.json"))
            {
                std::ifstream in(folder + "/summary.json");
                summary = nlohmann::json::parse(in, nullptr, false);
            }
            if (summary.is_discarded() || !summary.is_object())
            {
                c.status = "failed";
                c.message = "exit code 0 but no readable summary.json";
                ++results.failed;
            }
            else
            {
                try
                {
                    for (std::size_t o = 0; o < results.record.outputs.size(); ++o)
                    {
                        nlohmann::json scratch;
                        const nlohmann::json* value = outputValue(summary, results.record.outputs[o], scratch);
                        c.outputs[o] = value ? *value : nlohmann::json();
                    }
                    c.status = "done";
                    ++results.done;
                }
                catch (const InputError& e)
                {
                    // One case's broken summary is that case's failure: the others are still collected.
                    c.outputs.assign(results.record.outputs.size(), nullptr);
                    c.status = "failed";
                    c.message = e.what();
                    ++results.failed;
                }
            }
        }
        results.cases.push_back(std::move(c));
    }
    return results;
}

std::string resultsCsv(const StudyResults& results)
{
    std::ostringstream out;
    out << "case,status,exit_code";
    for (const StudyParameter& p : results.record.parameters)
    {
        out << "," << csvField(columnHeader(p.name, p.unit));
    }
    for (const StudyOutput& o : results.record.outputs)
    {
        out << "," << csvField(columnHeader(o.name, o.unit));
    }
    out << ",message\n";
    for (const CollectedCase& c : results.cases)
    {
        out << c.index << "," << c.status << "," << (c.exitCode >= 0 ? std::to_string(c.exitCode) : "");
        for (const nlohmann::json& v : c.values)
        {
            out << "," << csvField(cellText(v));
        }
        for (const nlohmann::json& v : c.outputs)
        {
            out << "," << csvField(cellText(v));
        }
        out << "," << csvField(c.message) << "\n";
    }
    return out.str();
}

std::string resultsTable(const StudyResults& results)
{
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> head = {"case"};
    for (const StudyParameter& p : results.record.parameters)
    {
        head.push_back(columnHeader(p.name, p.unit));
    }
    for (const StudyOutput& o : results.record.outputs)
    {
        head.push_back(columnHeader(o.name, o.unit));
    }
    head.push_back("status");
    rows.push_back(head);
    for (const CollectedCase& c : results.cases)
    {
        std::vector<std::string> row = {std::to_string(c.index)};
        for (const nlohmann::json& v : c.values)
        {
            row.push_back(cellText(v));
        }
        for (const nlohmann::json& v : c.outputs)
        {
            // Six significant digits on the terminal; results.csv keeps every digit.
            row.push_back(v.is_number_float() ? formatNumber("%.6g", v.get<double>()) : cellText(v));
        }
        row.push_back(c.status == "failed" ? "failed (exit " + std::to_string(c.exitCode) + "): " + c.message
                                           : c.status);
        rows.push_back(row);
    }
    std::vector<std::size_t> width(head.size(), 0);
    for (const auto& row : rows)
    {
        for (std::size_t i = 0; i + 1 < row.size(); ++i)
        {
            width[i] = std::max(width[i], row[i].size());
        }
    }
    std::ostringstream out;
    for (const auto& row : rows)
    {
        for (std::size_t i = 0; i < row.size(); ++i)
        {
            const bool last = i + 1 == row.size();
            out << (i ? "  " : "") << (last ? row[i] : std::string(width[i] - row[i].size(), ' ') + row[i]);
        }
        out << "\n";
    }
    return out.str();
}

std::vector<std::string> plotResults(const StudyResults& results, const std::string& dir)
{
    std::vector<std::string> written;
    const StudyRecord& record = results.record;
    const fs::path folder = fs::path(dir) / "plots";
    for (std::size_t o = 0; o < record.outputs.size(); ++o)
    {
        for (std::size_t p = 0; p < record.parameters.size(); ++p)
        {
            if (!allNumbers(results, p))
            {
                continue;
            }
            // With two varied keys, one line per value of the other (a grid's slices), if there are few of them.
            std::map<std::string, std::vector<std::pair<double, double>>> series;
            const std::size_t other = record.parameters.size() == 2 ? 1 - p : record.parameters.size();
            for (const CollectedCase& c : results.cases)
            {
                if (!c.outputs[o].is_number())
                {
                    continue;
                }
                const std::string group = other < record.parameters.size() ? cellText(c.values[other]) : "";
                series[group].emplace_back(c.values[p].get<double>(), c.outputs[o].get<double>());
            }
            if (series.empty())
            {
                continue;
            }
            const bool lines = series.size() > 1 && series.size() <= 8;
            if (!lines && series.size() > 1)
            {
                std::vector<std::pair<double, double>> all;
                for (const auto& s : series)
                {
                    all.insert(all.end(), s.second.begin(), s.second.end());
                }
                series = {{"", all}};
            }
            std::ostringstream script;
            script << "$data << EOD\n";
            for (auto& s : series)
            {
                std::sort(s.second.begin(), s.second.end());
                for (const auto& [x, y] : s.second)
                {
                    script << valueText(x) << " " << valueText(y) << "\n";
                }
                script << "\n\n";
            }
            script << "EOD\n";
            const std::string outputLabel = columnHeader(record.outputs[o].name, record.outputs[o].unit);
            script << "set title '" << gnuplotText(record.name + ": " + outputLabel) << "' noenhanced\n"
                   << "set xlabel '" << gnuplotText(columnHeader(record.parameters[p].name, record.parameters[p].unit))
                   << "' noenhanced\n"
                   << "set ylabel '" << gnuplotText(outputLabel) << "' noenhanced\n"
                   << "set grid\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n";
            if (lines)
            {
                script << "set key outside right title '"
                       << gnuplotText(columnHeader(record.parameters[other].name, record.parameters[other].unit))
                       << "' noenhanced\n";
            }
            else
            {
                script << "unset key\n";
            }
            script << "plot ";
            std::size_t block = 0;
            for (const auto& s : series)
            {
                script << (block ? ", " : "") << "$data index " << block << " with linespoints pt 7 lw 2 title '"
                       << gnuplotText(s.first) << "' noenhanced";
                ++block;
            }
            script << "\n";
            fs::create_directories(folder);
            const std::string png =
                (folder / (fileWord(record.outputs[o].name) + "-vs-" + fileWord(record.parameters[p].name) + ".png"))
                    .string();
            plotPng(script.str(), png);
            written.push_back(png);
        }
    }
    return written;
}
} // namespace masse::scene
