// tether's report of an identification or a fit (docs/reports.md): draws the JSON in #tether-report (what
// cli/fit_report.cc writes: the command's JSON, each recorded column with its residuals' statistics and
// histogram, the constrained columns, the estimate's run) as tables and canvas plots. #tether-report-probe holds,
// once drawn, what was drawn (for the browser tests).
(function() {
'use strict';
var report = JSON.parse(document.getElementById('tether-report').textContent);

function element(tag, text, className) {
  var e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (className) e.className = className;
  return e;
}
function number(x, digits) {
  return x === null || x === undefined ? '-' : Number(x).toPrecision(digits || 4);
}
function row(table, cells, header, classNames) {
  var tr = element('tr');
  cells.forEach(function(cell, k) {
    tr.appendChild(element(header ? 'th' : 'td', cell, classNames && classNames[k]));
  });
  table.appendChild(tr);
  return tr;
}

// a plot: lines and dots in data coordinates, or a histogram's bars, on a canvas with its axes
function plot(canvas, options) {
  var width = canvas.clientWidth || 340, height = canvas.clientHeight || 200, ratio = window.devicePixelRatio || 1;
  canvas.width = width * ratio;
  canvas.height = height * ratio;
  var g = canvas.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  var x0 = options.x[0], x1 = options.x[1], y0 = options.y[0], y1 = options.y[1];
  if (!(x1 > x0)) x1 = x0 + 1;
  if (!(y1 > y0)) {
    y0 -= 1;
    y1 = y0 + 2;
  }
  var left = 58, right = width - 8, top = 18, bottom = height - 24;
  function X(x) {
    return left + (x - x0) / (x1 - x0) * (right - left);
  }
  function Y(y) {
    return bottom - (y - y0) / (y1 - y0) * (bottom - top);
  }
  g.fillStyle = '#222';
  g.font = '11px sans-serif';
  g.fillText(options.title, left, 12);
  g.strokeStyle = '#999';
  g.strokeRect(left, top, right - left, bottom - top);
  g.fillText(number(y1, 3), 2, top + 8);
  g.fillText(number(y0, 3), 2, bottom);
  g.fillText(number(x0, 3), left, height - 8);
  g.fillText(number(x1, 3) + ' ' + (options.xUnit || ''), right - 60, height - 8);
  g.save();
  g.beginPath();
  g.rect(left, top, right - left, bottom - top);
  g.clip();
  (options.bars || []).forEach(function(bar) {
    g.fillStyle = '#9db8d6';
    g.fillRect(X(bar[0]), Y(bar[2]), X(bar[1]) - X(bar[0]) - 1, Y(0) - Y(bar[2]));
  });
  (options.lines || []).forEach(function(line) {
    g.strokeStyle = line.color;
    g.lineWidth = 1.3;
    g.setLineDash(line.dash || []);
    g.beginPath();
    var pen = false;
    line.x.forEach(function(x, k) {
      var y = line.y[k];
      if (y === null) {
        pen = false;
        return;
      }
      if (pen)
        g.lineTo(X(x), Y(y));
      else
        g.moveTo(X(x), Y(y));
      pen = true;
    });
    g.stroke();
    g.setLineDash([]);
  });
  (options.dots || []).forEach(function(set) {
    g.fillStyle = set.color;
    set.x.forEach(function(x, k) {
      if (set.y[k] !== null) g.fillRect(X(x) - 1.5, Y(set.y[k]) - 1.5, 3, 3);
    });
  });
  (options.marks || []).forEach(function(mark) {  // a bound: a segment over its interval, or a triangle
    g.strokeStyle = g.fillStyle = '#c0392b';
    g.lineWidth = 2;
    g.beginPath();
    if (mark.from < mark.t) {
      g.moveTo(X(mark.from), Y(mark.value));
      g.lineTo(X(mark.t), Y(mark.value));
      g.stroke();
    } else {
      var x = X(mark.t), y = Y(mark.value), d = mark.at_least ? 6 : -6;
      g.moveTo(x - 5, y + d);
      g.lineTo(x + 5, y + d);
      g.lineTo(x, y);
      g.fill();
    }
  });
  g.restore();
}
function range(arrays, tight) {
  var low = Infinity, high = -Infinity;
  arrays.forEach(function(values) {
    values.forEach(function(v) {
      if (v !== null && isFinite(v)) {
        low = Math.min(low, v);
        high = Math.max(high, v);
      }
    });
  });
  if (!isFinite(low)) return [0, 1];
  var pad = tight && high > low ? 0 : (high - low) * 0.05 || Math.abs(high) * 0.05 || 1;
  return [low - pad, high + pad];
}
function canvasIn(parent) {
  return parent.appendChild(element('canvas'));
}

// the summary and the warnings
var summary = document.getElementById('summary');
var line = element('p');
line.appendChild(document.createTextNode(
    'tether ' + report.command + ' of ' + report.scene + (report.data.length ? ' from ' + report.data.join(', ') : '') +
    ': ' + report.stopping_reason + ' (' + report.optimizer + ', ' + report.evaluations + ' evaluations, ' +
    number(report.seconds, 3) + ' s; cost ' + number(report.initial_cost) + ' to ' + number(report.final_cost) +
    ' over ' + report.residual_count + ' residuals; derivatives ' + report.gradient_method +
    (report.segments > 1 ? ', ' + report.segments + ' segments' : '') + '). '));
if (report.failed) line.appendChild(element('span', 'The estimate does not reproduce the data: failed.', 'failed'));
summary.appendChild(line);
var warnings = document.getElementById('warnings');
var said = report.warnings.slice();
if (report.run_diverged) said.push('the estimate\'s run: ' + report.run_diverged);
report.run_warnings.forEach(function(warning) {
  said.push('the estimate\'s run: ' + warning);
});
said.forEach(function(warning) {
  warnings.appendChild(element('li', warning));
});

// the parameters and their correlations
var parameters = document.getElementById('parameters');
row(parameters, ['#', 'parameter', 'initial', 'estimate', 'standard deviation', 'relative', '95% interval'], true,
    [undefined, 'name']);
report.pointers.forEach(function(pointer, k) {
  var estimate = report.parameters[pointer], sd = report.standard_deviation[pointer];
  row(parameters,
      [
        String(k + 1), pointer, number(report.initial_parameters[pointer]), number(estimate), number(sd, 3),
        sd === null ? '-' : number(100 * sd / Math.abs(estimate), 3) + ' %',
        sd === null ? '-' : number(estimate - 1.96 * sd) + ' .. ' + number(estimate + 1.96 * sd)
      ],
      false, [undefined, 'name']);
});
var n = report.pointers.length, heat = document.getElementById('correlation'), cells = 0;
var correlated = report.pointers.some(function(a) {
  return report.pointers.some(function(b) {
    return report.correlation[a][b] !== null;
  });
});
heat.hidden = !correlated;
var close = [];
var cell = Math.max(14, Math.min(48, Math.floor(600 / Math.max(n, 1))));
heat.style.width = (n * cell + 40) + 'px';
heat.style.height = (n * cell + 40) + 'px';
if (correlated)
  (function() {
    var ratio = window.devicePixelRatio || 1;
    heat.width = (n * cell + 40) * ratio;
    heat.height = (n * cell + 40) * ratio;
    var g = heat.getContext('2d');
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    g.font = '10px sans-serif';
    report.pointers.forEach(function(a, i) {
      g.fillStyle = '#222';
      g.fillText(String(i + 1), 4, 24 + i * cell + cell / 2 + 3);
      g.fillText(String(i + 1), 40 + i * cell + cell / 2 - 3, 14);
      report.pointers.forEach(function(b, k) {
        var r = report.correlation[a][b];
        // red positive, blue negative, white none; grey where unavailable
        var shade = r === null ? null : Math.round(255 * (1 - Math.min(Math.abs(r), 1)));
        g.fillStyle = shade === null ? '#ccc' :
            r >= 0                   ? 'rgb(255,' + shade + ',' + shade + ')' :
                                       'rgb(' + shade + ',' + shade + ',255)';
        g.fillRect(40 + k * cell, 24 + i * cell, cell - 1, cell - 1);
        ++cells;
        if (cell >= 30 && r !== null) {
          g.fillStyle = Math.abs(r) > 0.6 ? '#fff' : '#222';
          g.fillText(r.toFixed(2), 40 + k * cell + 3, 24 + i * cell + cell / 2 + 3);
        }
        if (k > i && r !== null && Math.abs(r) > 0.95) close.push(a + ' and ' + b + ' (' + r.toFixed(3) + ')');
      });
    });
  })();
document.getElementById('correlation-note').textContent = !correlated ?
    'None: the fit estimated no uncertainty (the warnings say why; a trajectory fit to constraints has none).' :
    'Parameters by their number in the table; red positive, blue negative. ' +
        (close.length ? 'Nearly interchangeable (|r| > 0.95), the data tell apart only their combination: ' +
                 close.join('; ') + '.' :
                        'No pair is correlated beyond |r| = 0.95.');

// the constraints of a fit
var constraints = report.constraints || [];
document.getElementById('constraints-part').hidden = constraints.length === 0;
var constraintTable = document.getElementById('constraints');
row(constraintTable, ['column', 'bound', 'time', 'simulated', 'met'], true, ['name']);
constraints.forEach(function(c) {
  var bound = c.at_least !== undefined ? '>= ' + number(c.at_least) : '<= ' + number(c.at_most);
  var time = c.from !== undefined ? number(c.from, 3) + ' .. ' + number(c.t, 3) + ' s' : number(c.t, 3) + ' s';
  row(constraintTable, [c.column, bound, time, number(c.simulated), c.met ? 'yes' : 'no'], false, ['name']);
});

// every recorded column: the fit, the residuals against time, their histogram
var simulated = report.simulated;
function marksOf(column) {
  return report.constrained.filter(function(c) {
    return c.column === column;
  });
}
var columns = report.columns, histograms = [], kFewestForHistogram = 8;  // fewer residuals draw no histogram
document.getElementById('data-part').hidden = columns.length === 0;
var residualTable = document.getElementById('residuals');
row(residualTable, ['file', 'column', 'n', 'fit RMS', 'RMS', 'bias', 'lag-one autocorrelation', 'largest |r|'], true,
    ['name', 'name']);
var blocks = document.getElementById('columns');
columns.forEach(function(c) {
  var s = c.statistics, unit = c.unit ? ' (' + c.unit + ')' : '';
  var tr =
      row(residualTable,
          [
            c.file, c.column, s ? String(s.count) : '0', number(c.fit_rms, 3), s ? number(s.rms, 3) : '-',
            s ? number(s.bias, 3) : '-', s ? number(s.lag_one, 3) : '-', s ? number(s.largest, 3) : '-'
          ],
          false, ['name', 'name']);
  if (s && s.lag_one !== null && Math.abs(s.lag_one) > 0.5) tr.className = 'systematic';
  blocks.appendChild(element(
      'h3', c.file + ': ' + c.column + unit + (c.stride > 1 ? ' (every ' + c.stride + '-th point drawn)' : '')));
  var figures = blocks.appendChild(element('div', undefined, 'figures'));
  var line = simulated.columns[c.column] || [];
  plot(canvasIn(figures), {
    title: 'observed (dots) and simulated' + unit,
    xUnit: 's',
    x: range([c.t, simulated.t], true),
    y: range([c.observed, line]),
    lines: [{x: simulated.t, y: line, color: '#4e79a7'}],
    dots: [{x: c.t, y: c.observed, color: '#e15759'}],
    marks: marksOf(c.column)
  });
  plot(canvasIn(figures), {
    title: 'residual' + unit,
    xUnit: 's',
    x: range([c.t], true),
    y: range([c.residual, [0]]),
    lines: [{x: [c.t[0], c.t[c.t.length - 1]], y: [0, 0], color: '#999', dash: [4, 3]}],
    dots: [{x: c.t, y: c.residual, color: '#e15759'}]
  });
  if (!s || s.count < kFewestForHistogram) return;
  // the histogram as a density, beside N(0, sigma^2)
  var width = (s.high - s.low) / s.counts.length, bars = [], peak = 0;
  s.counts.forEach(function(count, k) {
    var density = count / (s.count * width);
    bars.push([s.low + k * width, s.low + (k + 1) * width, density]);
    peak = Math.max(peak, density);
  });
  var curve = {x: [], y: [], color: '#c0392b'};
  for (var k = 0; k <= 100; ++k) {
    var x = s.low + (s.high - s.low) * k / 100;
    curve.x.push(x);
    curve.y.push(s.sigma > 0 ? Math.exp(-0.5 * x * x / (s.sigma * s.sigma)) / (s.sigma * Math.sqrt(2 * Math.PI)) : 0);
    peak = Math.max(peak, curve.y[k]);
  }
  plot(canvasIn(figures), {
    title: 'residuals\' density and N(0, ' + number(s.sigma, 3) + '^2)',
    xUnit: c.unit,
    x: [s.low, s.high],
    y: [0, peak * 1.1],
    bars: bars,
    lines: [curve]
  });
  histograms.push(s.counts.reduce(function(a, b) {
    return a + b;
  }, 0));
});

// the constrained columns no recording holds
var constrainedOnly = report.constrained
                          .map(function(c) {
                            return c.column;
                          })
                          .filter(function(column, k, all) {
                            return all.indexOf(column) === k && !columns.some(function(c) {
                              return c.column === column;
                            });
                          });
document.getElementById('constrained-part').hidden = constrainedOnly.length === 0;
constrainedOnly.forEach(function(column) {
  var marks = marksOf(column), line = simulated.columns[column] || [];
  plot(canvasIn(document.getElementById('constrained')), {
    title: column + (marks[0].unit ? ' (' + marks[0].unit + ')' : '') + ', simulated, and its bounds',
    xUnit: 's',
    x: range([simulated.t], true),
    y: range([
      line, marks.map(function(m) {
        return m.value;
      })
    ]),
    lines: [{x: simulated.t, y: line, color: '#4e79a7'}],
    marks: marks
  });
});

// the scheduled forces and torques through their knots, over the run
var schedules = report.schedules;
document.getElementById('schedules-part').hidden = schedules.length === 0;
schedules.forEach(function(schedule) {
  var end = simulated.t.length ? simulated.t[simulated.t.length - 1] : schedule.t[schedule.t.length - 1];
  var first = schedule.t[0], last = schedule.t[schedule.t.length - 1];
  var x = [Math.min(0, first)].concat(schedule.t, [Math.max(end, last)]);
  var y = [schedule.values[0]].concat(schedule.values, [schedule.values[schedule.values.length - 1]]);
  plot(canvasIn(document.getElementById('schedules')), {
    title: schedule.label,
    xUnit: 's',
    x: range([x], true),
    y: range([y]),
    lines: [{x: x, y: y, color: '#b07aa1'}],
    dots: [{x: schedule.t, y: schedule.values, color: '#b07aa1'}]
  });
});

var motion = document.getElementById('motion');
var posed = report.data.length > 0;
document.getElementById('motion-note').textContent = !motion.getAttribute('srcdoc') ?
    'No motion to play: the estimate\'s run diverged.' :
    'The estimate\'s motion (tether view)' +
        (posed ? '; its plot draws the first recording\'s column of the same name dashed, and where that ' +
                 'recording holds every body\'s pose the recording is drawn as grey ghosts.' :
                 '.');
if (!motion.getAttribute('srcdoc')) motion.hidden = true;

document.getElementById('tether-report-probe').textContent = JSON.stringify({
  parameters: parameters.rows.length - 1,
  correlations: cells,
  columns: columns.length,
  histograms: histograms,
  constraints: constraintTable.rows.length - 1,
  constrained: constrainedOnly.length,
  schedules: schedules.length,
  warnings: said.length,
  canvases: document.querySelectorAll('canvas').length
});
})();
