/// @file test_browser.cpp
/// The report in a real browser: headless chromium opens the report of the fixture run
/// directory, the test checks that every plot was drawn (the page counts the plot elements that
/// its script marked data-rendered) with no script or console error, and saves a screenshot in
/// the build tree (tests/report/browser/report/report.png); the same for a page with
/// --compare-tables (tests/report/browser/compare/compare.png).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>

#include "manta/core/io.hpp"
#include "manta/report/report.hpp"
#include "table_copies.hpp"

namespace fs = std::filesystem;
using namespace manta::report;

namespace {

const fs::path fixture = fs::path(MANTA_SOURCE_DIR) / "tests/data/report/run";
const fs::path work = MANTA_REPORT_WORK_DIR;

/// Run a shell command; its exit status.
int shell(const std::string& cmd) {
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string chromium_or_fail() {
    const std::string c = find_chromium();
    if (c.empty())
        ADD_FAILURE() << "chromium not found on PATH: the browser test needs it; run "
                         "scripts/install-deps.sh (Debian package chromium)";
    return c;
}

/// Each test has its own folder and chromium profile under the work folder: CTest runs the two
/// tests at the same time, and two chromium processes on one profile fail (exit status 21).
fs::path folder(const std::string& tag) {
    const fs::path f = work / tag;
    fs::remove_all(f);
    fs::create_directories(f);
    return f;
}

std::string flags(const fs::path& dir) {
    return " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run"
           " --user-data-dir=" +
           (dir / "profile").string();
}

const char* const interaction_script = R"JS(<script>
(function () {
  function set(name, ok) { document.body.setAttribute(name, ok ? '1' : '0'); }
  var hit = document.querySelector('.plot[data-figure] svg rect[fill="transparent"]');
  var r = hit.getBoundingClientRect();
  hit.dispatchEvent(new MouseEvent('mousemove', {clientX: r.left + r.width / 2, clientY: r.top + r.height / 2, bubbles: true}));
  var box = hit.closest('.plot').querySelector('.readout');
  set('data-test-readout', box.style.display === 'block' && /=/.test(box.textContent) && /: /.test(box.textContent));
  var svg = document.querySelector('.plot[data-path] svg');
  svg.dispatchEvent(new MouseEvent('mousedown', {clientX: 100, clientY: 100, bubbles: true}));
  window.dispatchEvent(new MouseEvent('mousemove', {clientX: 140, clientY: 100}));
  window.dispatchEvent(new MouseEvent('mouseup', {}));
  set('data-test-rotate', /azimuth -80 deg/.test(svg.textContent));
  var before = svg.querySelector('polyline').getAttribute('points');
  svg.dispatchEvent(new WheelEvent('wheel', {deltaY: -300, bubbles: true, cancelable: true}));
  set('data-test-zoom', svg.querySelector('polyline').getAttribute('points') !== before);
  var menu = document.querySelector('select[data-group]');
  var plot = document.getElementById(menu.getAttribute('data-group'));
  var old = plot.getAttribute('data-figure');
  menu.selectedIndex = (menu.selectedIndex + 1) % menu.options.length;
  menu.dispatchEvent(new Event('change'));
  set('data-test-menu', plot.getAttribute('data-figure') !== old && plot.querySelector('svg') !== null &&
      plot.querySelector('.title').textContent === menu.options[menu.selectedIndex].text.replace('M = ', 'Static table at M = '));
})();
</script>
)JS";

int attr(const std::string& dom, const std::string& name) {
    std::smatch m;
    if (!std::regex_search(dom, m, std::regex(name + "=\"([0-9]+)\""))) return -1;
    return std::stoi(m[1].str());
}

/// Open `html` in headless chromium with the probe script appended: every plot drawn, no
/// error, the interactions work, no console message. `tag` names the files in the work folder.
void check_page(const std::string& chromium, const fs::path& html, int plots,
                const std::string& tag) {
    const fs::path dir = html.parent_path();
    std::string page = manta::core::read_file(html);
    page.insert(page.rfind("</body>"), interaction_script);
    const fs::path probed = dir / (tag + "_probed.html");
    manta::core::write_file_atomic(probed, page);

    const fs::path dom = dir / (tag + "_dom.html"), log = dir / (tag + "_console.txt");
    const int rc = shell("'" + chromium + "'" + flags(dir) +
                         " --enable-logging=stderr --v=0 --dump-dom 'file://" + probed.string() +
                         "' > '" + dom.string() + "' 2> '" + log.string() + "'");
    ASSERT_EQ(rc, 0) << "chromium --dump-dom failed; see " << log;
    const std::string d = manta::core::read_file(dom);
    const int total = attr(d, "data-plots-total"), rendered = attr(d, "data-plots-rendered");
    EXPECT_EQ(total, plots) << tag << ": plot elements in the page";
    EXPECT_EQ(rendered, total) << tag << ": plots drawn by the page's script";
    EXPECT_EQ(attr(d, "data-errors"), 0) << tag << ": script errors caught by window.onerror:\n"
                                         << d.substr(d.find("id=\"errors\""), 400);
    EXPECT_EQ(attr(d, "data-test-readout"), 1) << tag << ": hover readout shown with values";
    EXPECT_EQ(attr(d, "data-test-rotate"), 1) << tag << ": drag rotated the 3-D path";
    EXPECT_EQ(attr(d, "data-test-zoom"), 1) << tag << ": the wheel zoomed the 3-D path";
    EXPECT_EQ(attr(d, "data-test-menu"), 1) << tag << ": a menu choice drew another slice";
    // Console messages chromium logs ("CONSOLE" lines): the page writes none.
    const std::string console = manta::core::read_file(log);
    std::size_t n_console = 0;
    for (auto k = console.find(":CONSOLE"); k != std::string::npos;
         k = console.find(":CONSOLE", k + 1))
        ++n_console;
    EXPECT_EQ(n_console, 0u) << console;

    const fs::path shot = dir / (tag + ".png");
    ASSERT_EQ(shell("'" + chromium + "'" + flags(dir) + " --window-size=1280,2000 --screenshot='" +
                    shot.string() + "' 'file://" + html.string() + "' > /dev/null 2>&1"),
              0);
    ASSERT_TRUE(fs::exists(shot));
    EXPECT_GT(fs::file_size(shot), 20000u) << "a blank page gives a tiny PNG";
}

}  // namespace

TEST(Browser, EveryPlotRendersWithoutErrorsAndAScreenshotIsSaved) {
    const std::string chromium = chromium_or_fail();
    if (chromium.empty()) return;
    ReportOptions o;
    o.run_dir = fixture;
    o.html = folder("report") / "report.html";
    (void)make_report(o);
    // Static, 3 controls, dynamic, histories, flight path, replay x3.
    check_page(chromium, o.html, 10, "report");
}

TEST(Browser, ComparisonPageRendersEveryPlot) {
    const std::string chromium = chromium_or_fail();
    if (chromium.empty()) return;
    ReportOptions o;
    o.run_dir = fixture;
    o.html = folder("compare") / "compare.html";
    o.compare_tables = manta::report::test_data::scaled_copy("browser", {"CL", "sigma_CL"}, 1.1);
    (void)make_report(o);
    // The 10 plots of the run, each static and control figure with both tables, and the
    // comparison's summary and dynamic-derivative figures.
    check_page(chromium, o.html, 12, "compare");
    fs::remove_all(*o.compare_tables);
}
