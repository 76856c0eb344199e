// tether's study index (docs/reports.md): draws the JSON in #tether-study (what cli/study_index.cc writes: the
// study's columns and rows, its figures and summary) as a sortable, filterable table beside the figures, and plays
// any row's run: its data, DIR/views/ROW.js, is loaded by a script element when asked (a page opened from disk may
// load scripts beside it, not read files) and poured into the viewer's page template (#tether-viewer-page) in a
// frame. #tether-study-probe holds what is shown (for the browser tests).
(function() {
'use strict';
var study = JSON.parse(document.getElementById('tether-study').textContent);
var template = JSON.parse(document.getElementById('tether-viewer-page').textContent);

function element(tag, text, className) {
  var e = document.createElement(tag);
  if (text !== undefined) e.textContent = text;
  if (className) e.className = className;
  return e;
}
function metricText(x) {
  if (x === null) return 'nan';
  if (typeof x !== 'number') return String(x);
  return Number.isInteger(x) ? String(x) : x.toPrecision(4);
}

// the summary
var counts = {};
study.rows.forEach(function(row) {
  var kind = row.status.split(':')[0];
  counts[kind] = (counts[kind] || 0) + 1;
});
document.getElementById('summary').textContent = 'Study ' + study.study +
    (study.scenes.length ? ' of ' + study.scenes.join(', ') : '') + ': ' + study.rows.length + ' runs over ' +
    study.pointers.join(', ') + '; ' +
    Object.keys(counts)
        .map(function(kind) {
          return counts[kind] + ' ' + kind;
        })
        .join(', ') +
    '. Metrics: ' + study.metrics.join(', ') + '.';
study.best.forEach(function(line) {
  document.getElementById('best').appendChild(element('li', line));
});
study.figures.forEach(function(name) {
  var figure = element('figure'), image = element('img');
  image.src = name;
  image.alt = name;
  figure.appendChild(image);
  var caption = element('figcaption', name + ' ');
  var vector = element('a', '(SVG)');
  vector.href = name.replace(/\.png$/, '.svg');
  caption.appendChild(vector);
  figure.appendChild(caption);
  document.getElementById('figures').appendChild(figure);
});

// the results: a row per run, a column per swept pointer and metric, its status and its view
// (a study whose rows keep no motion, a benchmark's, has no run column and no viewer)
var viewable = study.rows.some(function(row) {
  return row.view;
});
document.getElementById('viewer-box').hidden = !viewable;
var columns = ['#'].concat(study.pointers, study.metrics, viewable ? ['status', 'run'] : ['status']);
var table = document.getElementById('results'), head = element('tr'), sortColumn = 0, ascending = true;
columns.forEach(function(name, c) {
  var th = element('th', name);
  th.addEventListener('click', function() {
    ascending = sortColumn === c ? !ascending : true;
    sortColumn = c;
    order();
  });
  head.appendChild(th);
});
table.appendChild(head);
function cellOf(row, c) {  // the value a column sorts by
  if (c === 0) return row.index;
  c -= 1;
  if (c < study.pointers.length) return row.values[c];
  c -= study.pointers.length;
  if (c < study.metrics.length) return row.metrics[c];
  return c === 0 ? row.status : (row.view ? 1 : 0);
}
var viewing = -1, loaded = null, lines = study.rows.map(function(row) {
  var tr = element('tr', undefined, row.status.split(':')[0] === 'ok' ? '' : 'not-ok');
  tr.appendChild(element('td', String(row.index)));
  row.values.forEach(function(v) {
    tr.appendChild(element('td', String(v), typeof v === 'number' ? '' : 'text'));
  });
  row.metrics.forEach(function(m) {
    tr.appendChild(element('td', metricText(m)));
  });
  var status = element('td', row.status, 'status');
  status.title = row.status;
  tr.appendChild(status);
  tr.userData = row;
  if (!viewable) return tr;
  var run = element('td');
  if (row.view) {
    var button = element('button', 'view');
    button.type = 'button';
    button.addEventListener('click', function() {
      show(row.index);
    });
    run.appendChild(button);
  } else {
    run.textContent = '-';
    run.title = 'no motion kept (a run that diverged, or one too large for a page, keeps none)';
  }
  tr.appendChild(run);
  return tr;
});
function order() {
  var sorted = lines.slice().sort(function(a, b) {
    var x = cellOf(a.userData, sortColumn), y = cellOf(b.userData, sortColumn);
    if (x === y) return a.userData.index - b.userData.index;
    if (x === null) return 1;  // nan last, either way
    if (y === null) return -1;
    var less = typeof x === 'number' && typeof y === 'number' ? x < y : String(x) < String(y);
    return (less ? -1 : 1) * (ascending ? 1 : -1);
  });
  sorted.forEach(function(tr) {
    table.appendChild(tr);
  });
  head.childNodes.forEach(function(th, c) {
    th.className = c === sortColumn ? 'sorted' : '';
  });
  probe();
}
var filter = document.getElementById('filter');
filter.addEventListener('input', function() {
  var text = filter.value.toLowerCase();
  lines.forEach(function(tr) {
    tr.hidden = text !== '' && tr.textContent.toLowerCase().indexOf(text) < 0;
  });
  probe();
});

// a row's run: its script calls tetherStudyRow(data) once loaded, data.row its index
var frame = document.getElementById('row-view'), note = document.getElementById('viewer-note');
window.tetherStudyRow = function(data) {
  var index = data.row, row = study.rows[index];
  if (JSON.stringify(data.values) !== JSON.stringify(row.values)) {  // left by another study in this folder
    note.textContent = 'views/' + index + '.js holds another run than row ' + index +
        ' (an earlier study in this folder): run the study again to refresh it.';
    frame.hidden = true;
    return;
  }
  loaded = {row: index, frames: data.frames.times.length};
  note.textContent = 'Row ' + index + ': ' +
      study.pointers
          .map(function(p, k) {
            return p + ' = ' + String(row.values[k]);
          })
          .join(', ') +
      ' (' + row.status.split(':')[0] + ')';
  var json = JSON.stringify(data).replace(/<\//g, '<\\/');
  frame.srcdoc = template.replace('@DATA@', function() {
    return json;
  });
  frame.hidden = false;
  probe();
};
function show(index) {
  viewing = index;
  lines.forEach(function(tr) {
    tr.classList.toggle('viewing', tr.userData.index === index);
  });
  var script = element('script');
  script.src = 'views/' + index + '.js';
  script.onerror = function() {
    note.textContent = 'views/' + index + '.js is missing beside index.html: run the study again to write it.';
    frame.hidden = true;
  };
  document.body.appendChild(script);
  probe();
}

function probe() {
  document.getElementById('tether-study-probe').textContent = JSON.stringify({
    rows: lines.length,
    shown: lines
               .filter(function(tr) {
                 return !tr.hidden;
               })
               .length,
    order: Array.prototype.slice.call(table.rows, 1).map(function(tr) {
      return tr.userData.index;
    }),
    figures: study.figures.length,
    viewing: viewing,
    loaded: loaded
  });
}
// index.html#sort=COLUMN (or #sort=-COLUMN, descending) opens sorted, #row=K with row K playing: "&" joins them
var sort = /[#&]sort=(-?)([^&]+)/.exec(window.location.hash);
if (sort && columns.indexOf(decodeURIComponent(sort[2])) >= 0) {
  sortColumn = columns.indexOf(decodeURIComponent(sort[2]));
  ascending = sort[1] !== '-';
}
order();
var asked = /[#&]row=(\d+)/.exec(window.location.hash);
if (asked && study.rows[parseInt(asked[1], 10)] && study.rows[parseInt(asked[1], 10)].view)
  show(parseInt(asked[1], 10));
})();
