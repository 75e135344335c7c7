// noise_peer: the other end of the secure-session interop test, written on
// flynn/noise (an independent Noise implementation, Debian's
// golang-github-flynn-noise-dev), nothing of Troupe's own. It speaks the
// framing of wire/README.md's "Secure sessions": every Noise message after
// a 2-byte big-endian length; the transport plaintexts form a stream of
// frames (u32 little-endian length, then the body).
//
//	responder: noise_peer -role responder -key SECRET_HEX -prologue TEXT
//	  listens on 127.0.0.1 (port printed as "listening PORT"), prints
//	  "client KEY_HEX" after the handshake, then answers every frame with
//	  the frame whose body bytes are each one more, until the peer closes.
//	initiator: noise_peer -role initiator -key SECRET_HEX -peer PUBLIC_HEX
//	  -prologue TEXT -connect HOST:PORT -send SIZE,SIZE,...
//	  sends one test frame of each body size (byte i of frame k is k + 7i),
//	  checks each answer is that frame with every body byte one more, and
//	  exits 0 ("interop ok") or 1 with the reason.
package main

import (
	"bytes"
	"encoding/binary"
	"encoding/hex"
	"flag"
	"fmt"
	"io"
	"net"
	"os"
	"strconv"
	"strings"

	"github.com/flynn/noise"
)

const maxPlain = 65535 - 16

func fail(format string, args ...interface{}) {
	fmt.Printf("error: "+format+"\n", args...)
	os.Exit(1)
}

func readMessage(c net.Conn) ([]byte, error) {
	var n [2]byte
	if _, err := io.ReadFull(c, n[:]); err != nil {
		return nil, err
	}
	m := make([]byte, binary.BigEndian.Uint16(n[:]))
	_, err := io.ReadFull(c, m)
	return m, err
}

func writeMessage(c net.Conn, m []byte) {
	var n [2]byte
	binary.BigEndian.PutUint16(n[:], uint16(len(m)))
	if _, err := c.Write(append(n[:], m...)); err != nil {
		fail("write: %v", err)
	}
}

// frames reads the frame stream out of transport messages.
type frames struct {
	conn    net.Conn
	receive *noise.CipherState
	pending []byte
}

func (f *frames) next() ([]byte, error) {
	for {
		if len(f.pending) >= 4 {
			n := 4 + int(binary.LittleEndian.Uint32(f.pending))
			if len(f.pending) >= n {
				frame := append([]byte(nil), f.pending[:n]...)
				f.pending = f.pending[n:]
				return frame, nil
			}
		}
		m, err := readMessage(f.conn)
		if err != nil {
			return nil, err
		}
		plain, err := f.receive.Decrypt(nil, nil, m)
		if err != nil {
			fail("transport message %d does not authenticate: %v", f.receive.Nonce(), err)
		}
		f.pending = append(f.pending, plain...)
	}
}

// send seals a frame in as many transport messages as it needs.
func send(c net.Conn, cs *noise.CipherState, frame []byte) {
	for len(frame) > 0 {
		n := len(frame)
		if n > maxPlain {
			n = maxPlain
		}
		m, err := cs.Encrypt(nil, nil, frame[:n])
		if err != nil {
			fail("encrypt: %v", err)
		}
		writeMessage(c, m)
		frame = frame[n:]
	}
}

func testFrame(size int, seed byte) []byte {
	f := make([]byte, 4+size)
	binary.LittleEndian.PutUint32(f, uint32(size))
	for i := 0; i < size; i++ {
		f[4+i] = seed + byte(i*7)
	}
	return f
}

func answer(frame []byte) []byte {
	out := append([]byte(nil), frame...)
	for i := 4; i < len(out); i++ {
		out[i]++
	}
	return out
}

func main() {
	role := flag.String("role", "responder", "initiator or responder")
	keyHex := flag.String("key", "", "our X25519 secret key, hex")
	peerHex := flag.String("peer", "", "the responder's public key, hex (initiator)")
	prologue := flag.String("prologue", "", "the Noise prologue")
	connect := flag.String("connect", "", "HOST:PORT to connect to (initiator)")
	sizes := flag.String("send", "", "frame body sizes to send, comma-separated (initiator)")
	flag.Parse()

	secret, err := hex.DecodeString(*keyHex)
	if err != nil || len(secret) != 32 {
		fail("-key needs 32 bytes of hex")
	}
	static, err := noise.DH25519.GenerateKeypair(bytes.NewReader(secret))
	if err != nil {
		fail("key: %v", err)
	}
	initiator := *role == "initiator"
	config := noise.Config{
		CipherSuite:   noise.NewCipherSuite(noise.DH25519, noise.CipherChaChaPoly, noise.HashBLAKE2b),
		Pattern:       noise.HandshakeIK,
		Initiator:     initiator,
		Prologue:      []byte(*prologue),
		StaticKeypair: static,
	}
	if initiator {
		if config.PeerStatic, err = hex.DecodeString(*peerHex); err != nil || len(config.PeerStatic) != 32 {
			fail("-peer needs 32 bytes of hex")
		}
	}
	hs, err := noise.NewHandshakeState(config)
	if err != nil {
		fail("handshake state: %v", err)
	}

	var conn net.Conn
	if initiator {
		if conn, err = net.Dial("tcp", *connect); err != nil {
			fail("connect: %v", err)
		}
	} else {
		ln, err := net.Listen("tcp", "127.0.0.1:0")
		if err != nil {
			fail("listen: %v", err)
		}
		fmt.Printf("listening %d\n", ln.Addr().(*net.TCPAddr).Port)
		if conn, err = ln.Accept(); err != nil {
			fail("accept: %v", err)
		}
		ln.Close()
	}
	defer conn.Close()

	// IK: the initiator writes message 1 and reads message 2; the first
	// CipherState of the split carries initiator to responder.
	var sendCS, receiveCS *noise.CipherState
	if initiator {
		m, _, _, err := hs.WriteMessage(nil, nil)
		if err != nil {
			fail("write message 1: %v", err)
		}
		writeMessage(conn, m)
		reply, err := readMessage(conn)
		if err != nil {
			fail("no handshake answer: %v", err)
		}
		var c0, c1 *noise.CipherState
		if _, c0, c1, err = hs.ReadMessage(nil, reply); err != nil {
			fail("message 2 does not authenticate: %v", err)
		}
		sendCS, receiveCS = c0, c1
	} else {
		m, err := readMessage(conn)
		if err != nil {
			fail("no handshake: %v", err)
		}
		if _, _, _, err = hs.ReadMessage(nil, m); err != nil {
			fail("message 1 does not authenticate: %v", err)
		}
		fmt.Printf("client %x\n", hs.PeerStatic())
		reply, c0, c1, err := hs.WriteMessage(nil, nil)
		if err != nil {
			fail("write message 2: %v", err)
		}
		writeMessage(conn, reply)
		sendCS, receiveCS = c1, c0
	}
	in := &frames{conn: conn, receive: receiveCS}

	if !initiator {
		for {
			frame, err := in.next()
			if err != nil {
				fmt.Println("peer closed")
				return
			}
			send(conn, sendCS, answer(frame))
		}
	}
	for k, s := range strings.Split(*sizes, ",") {
		size, err := strconv.Atoi(s)
		if err != nil {
			fail("-send: %v", err)
		}
		frame := testFrame(size, byte(k))
		send(conn, sendCS, frame)
		got, err := in.next()
		if err != nil {
			fail("no answer to frame %d: %v", k, err)
		}
		if !bytes.Equal(got, answer(frame)) {
			fail("answer to frame %d (%d bytes) differs", k, size)
		}
	}
	fmt.Println("interop ok")
}
