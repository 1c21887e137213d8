/* The site's search runs in a web worker, and a page opened as a file (file://) may not start
   one. There, run the worker's script in a hidden frame of the page's own origin instead, with
   the same messages both ways, so that search works in the site as files, with no server and
   no network. Over http(s) nothing changes. */
(function () {
  "use strict";
  if (location.protocol !== "file:") return;

  function FileWorker(url) {
    var worker = this;
    this.onmessage = null;
    this.onerror = null;
    this.listeners = [];
    this.waiting = [];
    this.frame = document.createElement("iframe");
    this.frame.style.display = "none";
    document.documentElement.appendChild(this.frame);
    var scope = this.frame.contentWindow;
    scope.postMessage = function (data) { setTimeout(function () { worker.emit("message", data); }, 0); };
    scope.importScripts = function () { throw new Error("importScripts is not available from file://"); };
    var script = scope.document.createElement("script");
    script.src = new URL(url, location.href).href;
    script.onload = function () { worker.loaded = true; worker.waiting.splice(0).forEach(worker.deliver, worker); };
    script.onerror = function () { worker.emit("error", "cannot load " + url); };
    scope.document.head.appendChild(script);
  }

  FileWorker.prototype.deliver = function (data) {
    var scope = this.frame.contentWindow;
    scope.dispatchEvent(new scope.MessageEvent("message", { data: data }));
  };

  FileWorker.prototype.postMessage = function (data) {
    if (this.loaded) this.deliver(data); else this.waiting.push(data);
  };

  FileWorker.prototype.emit = function (type, data) {
    var event = { type: type, data: data, message: data, target: this };
    var handler = type === "message" ? this.onmessage : this.onerror;
    if (handler) handler.call(this, event);
    this.listeners.filter(function (l) { return l.type === type; })
      .forEach(function (l) { l.fn.call(this, event); }, this);
  };

  FileWorker.prototype.addEventListener = function (type, fn) { this.listeners.push({ type: type, fn: fn }); };
  FileWorker.prototype.removeEventListener = function (type, fn) {
    this.listeners = this.listeners.filter(function (l) { return l.type !== type || l.fn !== fn; });
  };
  FileWorker.prototype.terminate = function () { this.frame.remove(); };

  window.Worker = FileWorker;
})();
